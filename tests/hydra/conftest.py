"""Hydra tests run OpenUSD's own tools (usdrecord, and scripts on its FrameRecorder) in child
processes with the OpenUSD build's Python and `pxr`; this process keeps the venv's usd-core,
so the two `pxr` builds never meet in one interpreter."""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))

OPENUSD = Path(os.environ.get("GI_OPENUSD_ROOT", "/opt/openusd"))
PLUGIN = os.environ.get("GI_HYDRA_PLUGIN", str(REPO / "build/hydra/hdGi-plugin/hdGi/resources"))
CORNELL = REPO / "scenes/cornell/cornell.usda"

if not (OPENUSD / "pxrConfig.cmake").exists() or not Path(PLUGIN, "plugInfo.json").exists():
    pytest.skip(f"no OpenUSD build at {OPENUSD} or no hdGi plugin at {PLUGIN}", allow_module_level=True)


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
    return env


def run_openusd(args, timeout=900):
    """Runs an OpenUSD tool or script; returns the completed process (output captured)."""
    result = subprocess.run(args, env=openusd_env(), capture_output=True, text=True, timeout=timeout)
    if result.returncode != 0:
        raise AssertionError(f"{' '.join(map(str, args))} failed ({result.returncode}):\n"
                             f"{result.stdout[-4000:]}\n{result.stderr[-4000:]}")
    return result


def hdgi_errors(text):
    """Lines where Hydra or hdGi reported a coding/runtime error."""
    return [line for line in text.splitlines()
            if "Coding Error" in line or "Runtime Error" in line or "Traceback" in line]


def read_rgb(path):
    from gi import _core
    pixels, _metadata = _core.read_image(str(path))
    image = np.asarray(pixels, dtype=np.float64)
    return image[..., :3]


def settings_layer(path, **settings):
    """A session layer setting gi:* attributes on the Cornell box's render settings prim."""
    lines = ["#usda 1.0", 'over "Render"', "{", '    over "Settings"', "    {"]
    for key, value in settings.items():
        kind = "string" if isinstance(value, str) else "float" if isinstance(value, float) else "int"
        literal = f'"{value}"' if isinstance(value, str) else repr(value)
        lines.append(f"        custom {kind} gi:{key.replace('__', ':')} = {literal}")
    lines += ["    }", "}", ""]
    Path(path).write_text("\n".join(lines))
    return path
