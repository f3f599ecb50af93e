"""The Hydra path against `gi render` for the same work: per scene, the time to open the stage,
Hydra's sync (the first Render call), hdGi's scene build (Embree BVH included), the time to the
first pixels (a low-resolution preview in views of 256x256 and more) and to the first full pass,
and the wall time of a converged render through UsdImagingGL (usdrecord's engine) against
`gi render` with the same integrator, samples, seed and resolution; the ratio is the cost of the
Hydra path (target: at most 1.10). Then, per scene, interactive edits of the stage's first mesh:
moved three times in one session, hidden and shown again, bound to another material and back,
with the scene build, the BVH primitives built, kept and masked, and the times to the first new
pixels and the first new pass after each (an edit builds what it changed alone and masks its old
self in the BVH it keeps). With --usdview, also usdview itself (under
xvfb-run, Mesa's software OpenGL): the viewport's size and, for the render it starts on opening each
scene with Gi's defaults, the times to the first pixels and the first full pass, and how long the
render before it ran (usdview resizes its viewport after its first draw, which restarts the render).
Needs the OpenUSD build and the plugin (scripts/test-hydra.sh).

    .venv/bin/python bench/hydra.py [--samples N] [--width W] [--usdview] [SCENE ...]
"""
import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests/hydra"))
from openusd import available, openusd_env, openusd_python  # noqa: E402

DEFAULT_SCENES = ("scenes/cornell/cornell.usda", "scenes/sibenik/sibenik.usda", "scenes/sponza/sponza.usda")


def hydra(scene, width, integrator, samples, edit=""):
    script = ROOT / "tests/hydra/scripts/record_stats.py"
    out = subprocess.run([openusd_python(), str(script), str(scene), str(width), integrator, str(samples), "0", edit],
                         env=openusd_env(), capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def usdview_first_pass(scene):
    """usdview opening SCENE with Gi and the render settings' camera: tests/hydra/scripts/usdview_first_pass.py."""
    from pxr import Usd, UsdGeom  # usd-core's, only to find the camera's path
    stage = Usd.Stage.Open(str(scene))
    settings = stage.GetPrimAtPath(stage.GetMetadata("renderSettingsPrimPath") or "/")
    cameras = settings.GetRelationship("camera").GetForwardedTargets() if settings.HasRelationship("camera") else []
    camera = cameras[0] if cameras else next(p.GetPath() for p in stage.Traverse() if p.IsA(UsdGeom.Camera))
    with tempfile.TemporaryDirectory() as out:
        env = openusd_env()
        env["GI_USDVIEW_OUT"] = out
        testusdview = Path(env["PATH"].split(":")[0]) / "testusdview"
        subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", str(testusdview), "--testScript",
                        str(ROOT / "tests/hydra/scripts/usdview_first_pass.py"), "--renderer", "Gi", "--camera",
                        str(camera), str(scene)], env=env, capture_output=True, text=True, timeout=900)
        result = Path(out, "first_pass.json")
        if not result.exists():
            sys.exit(f"bench/hydra.py: usdview wrote no result for {scene}")
        return json.loads(result.read_text())


def cli(scene, width, height, integrator, samples):
    start = time.perf_counter()
    subprocess.run([str(ROOT / ".venv/bin/gi"), "render", str(scene), "--integrator", integrator, "--spp",
                    str(samples), "--resolution", str(width), str(height), "-o", "/tmp/gi-bench-hydra.exr",
                    "--no-png"], check=True, capture_output=True)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=[s for s in DEFAULT_SCENES if (ROOT / s).exists()])
    parser.add_argument("--samples", type=int, default=64)
    parser.add_argument("--width", type=int, default=512)
    parser.add_argument("--integrator", default="path")
    parser.add_argument("--usdview", action="store_true", help="also time usdview's first pass on each scene")
    args = parser.parse_args()
    if not available():
        sys.exit("bench/hydra.py: no OpenUSD build or no hdGi plugin (run scripts/test-hydra.sh first)")
    print(f"{'scene':28} {'open s':>7} {'sync s':>7} {'build s':>8} {'1st px s':>8} {'1st pass':>8} "
          f"{'hydra s':>8} {'gi s':>7} {'ratio':>6}")
    for scene in args.scenes:
        h = hydra(ROOT / scene, args.width, args.integrator, args.samples)
        g = cli(ROOT / scene, h["width"], h["height"], args.integrator, args.samples)
        s = h["stats"]
        print(f"{Path(scene).name:28} {h['open_seconds']:7.2f} {h['sync_seconds']:7.2f} "
              f"{float(s.get('sceneBuildSeconds', 0)):8.2f} {float(s.get('firstPixelSeconds', 0)):8.2f} "
              f"{float(s.get('firstPassSeconds', 0)):8.2f} {h['wall_seconds']:8.2f} {g:7.2f} {h['wall_seconds'] / g:6.2f}")
    print(f"\n{'scene: one mesh edited':28} {'edit':>8} {'build s':>8} {'built':>9} {'kept':>9} {'masked':>7} "
          f"{'1st px s':>9} {'1st pass s':>10}")
    for scene in args.scenes:
        h = hydra(ROOT / scene, args.width, args.integrator, 1, "move")
        rows = [("load", h["stats"])] + [(f"move {i + 1}", s) for i, s in enumerate(h["stats_after_moves"])]
        for edit, labels in (("hide", ("hide", "show")), ("material", ("rebind", "restore"))):
            e = hydra(ROOT / scene, args.width, args.integrator, 1, edit)
            rows += list(zip(labels, e["stats_after_edits"]))
        for edit, s in rows:
            print(f"{Path(scene).name + ' ' + h['moved'].split('/')[-1]:28.28} {edit:>8} "
                  f"{float(s.get('sceneBuildSeconds', 0)):8.3f} {int(s.get('primitivesBuilt', 0)):9,} "
                  f"{int(s.get('primitivesReused', 0)):9,} {int(s.get('primitivesMasked', 0)):7,} "
                  f"{float(s.get('firstPixelSeconds', 0)):9.3f} {float(s.get('firstPassSeconds', 0)):10.3f}")
    if not args.usdview:
        return
    if not shutil.which("xvfb-run"):
        sys.exit("bench/hydra.py --usdview: needs xvfb-run")
    print(f"\n{'usdview opens the scene':28} {'viewport':>9} {'restarted s':>11} {'1st px s':>9} {'1st pass s':>10}")
    for scene in args.scenes:
        u = usdview_first_pass(ROOT / scene)
        s = u["stats"]
        print(f"{Path(scene).name:28} {'x'.join(map(str, u['viewport'])):>9} "
              f"{u['restarted_render_seconds']:11.3f} {float(s.get('firstPixelSeconds', 0)):9.3f} "
              f"{float(s.get('firstPassSeconds', 0)):10.3f}")


if __name__ == "__main__":
    main()
