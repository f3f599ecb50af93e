"""Where the OpenUSD build and the hdGi plugin are, and how to run OpenUSD's tools in a child
process with the OpenUSD build's Python (never in this interpreter, which has usd-core's pxr)."""
import os
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
OPENUSD = Path(os.environ.get("GI_OPENUSD_ROOT", "/opt/openusd"))
PLUGIN = os.environ.get("GI_HYDRA_PLUGIN", str(REPO / "build/hydra/hdGi-plugin/hdGi/resources"))


def available():
    return (OPENUSD / "pxrConfig.cmake").exists() and Path(PLUGIN, "plugInfo.json").exists()


def openusd_python():
    """The interpreter OpenUSD was built with (usdrecord's shebang)."""
    first = (OPENUSD / "bin/usdrecord").read_text().splitlines()[0]
    return first[2:].strip().split()[0]


def openusd_env():
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    env["PYTHONPATH"] = str(OPENUSD / "lib/python")
    env["PATH"] = f"{OPENUSD / 'bin'}:{env.get('PATH', '')}"
    env["LD_LIBRARY_PATH"] = f"{OPENUSD / 'lib'}:{env.get('LD_LIBRARY_PATH', '')}"
    env["PXR_PLUGINPATH_NAME"] = PLUGIN
    # UsdImaging's scene-index path gives Gi its sphere prims; the legacy delegate (24.11's
    # default) tessellates every sphere into a mesh.
    env["USDIMAGINGGL_ENGINE_ENABLE_SCENE_INDEX"] = "1"
    return env


def run_openusd(args, timeout=900, scene_index=True):
    """Runs an OpenUSD tool or script; returns the completed process (output captured).
    scene_index=False: through UsdImaging's legacy scene delegate instead."""
    env = openusd_env()
    if not scene_index:
        env["USDIMAGINGGL_ENGINE_ENABLE_SCENE_INDEX"] = "0"
    result = subprocess.run(args, env=env, capture_output=True, text=True, timeout=timeout)
    if result.returncode != 0:
        raise AssertionError(f"{' '.join(map(str, args))} failed ({result.returncode}):\n"
                             f"{result.stdout[-4000:]}\n{result.stderr[-4000:]}")
    return result
