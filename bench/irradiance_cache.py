"""Irradiance caching at full resolution: records, preprocessing and render time, and peak memory,
per scene and integrator (issue 4: Sponza must stay under 2 GB at 1024x768).

Each scene x integrator runs in its own process, because peak memory is a process high-water mark:
the stage is loaded, the scene committed, and the integrator renders at the resolution given
(default 1024x768) with the integrator's default parameters unless --param says otherwise. Printed:
records in the cache, preprocessing (the cache fill; for the adaptive cache also its refinement)
and render seconds, the process's peak resident memory, what rendering added to the peak reached by
loading, and the cache's own bytes.

    .venv/bin/python bench/irradiance_cache.py                       # Cornell box and Sponza, both caches
    .venv/bin/python bench/irradiance_cache.py scenes/sibenik/sibenik.usda --spp 1 --param paths=64
"""
import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_SCENES = ("cornell", "sponza")
INTEGRATORS = ("irradianceCache", "adaptiveIrradianceCache")
LIMIT_MB = {"sponza.usda": 2048}


def measure(scene, integrator, width, height, spp, params):
    """Runs in the child process."""
    import gi
    from gi import _core
    from gi.render import render_loaded, render_settings
    start = time.perf_counter()
    loaded = gi.load_stage(str(scene))
    loaded.scene.commit()
    load_seconds = time.perf_counter() - start
    loaded_peak = _core.peak_memory_bytes()
    settings = render_settings(loaded, integrator, params, spp, 0, 0, 0.0, (width, height), "box")
    start = time.perf_counter()
    result = render_loaded(loaded, settings, integrator)
    wall = time.perf_counter() - start
    s = result.stats
    return {"scene": str(scene), "integrator": integrator, "width": width, "height": height, "spp": spp,
            "records": int(s.get("records", 0)), "render_time_records": int(s.get("renderTimeRecords", 0)),
            "load_s": load_seconds, "preprocess_s": s["preprocess_seconds"], "render_s": s["render_seconds"],
            "wall_s": wall, "peak_mb": _core.peak_memory_bytes() / 2**20,
            "added_mb": (_core.peak_memory_bytes() - loaded_peak) / 2**20,
            "cache_mb": s.get("cacheBytes", 0) / 2**20,
            "refinement_s": s.get("refinementSeconds", 0.0), "shading_points": int(s.get("shadingPoints", 0))}


def run_child(scene, integrator, args):
    command = [sys.executable, __file__, str(scene), "--child", integrator, "--resolution", str(args.resolution[0]),
               str(args.resolution[1]), "--spp", str(args.spp)] + [x for p in args.param for x in ("--param", p)]
    proc = subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
    if proc.returncode != 0:
        return {"scene": str(scene), "integrator": integrator,
                "error": (proc.stderr.strip().splitlines() or ["failed"])[-1]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def parse_params(pairs):
    params = {}
    for pair in pairs:
        name, _, value = pair.partition("=")
        params[name] = float(value)
    return params


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", type=Path,
                        default=[ROOT / "scenes" / name / f"{name}.usda" for name in DEFAULT_SCENES],
                        help=f"USD scenes (default: {', '.join(DEFAULT_SCENES)})")
    parser.add_argument("--integrators", default=",".join(INTEGRATORS), help="comma-separated (default: both caches)")
    parser.add_argument("--resolution", type=int, nargs=2, default=(1024, 768), metavar=("W", "H"))
    parser.add_argument("--spp", type=int, default=4, help="camera samples per pixel (default 4)")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="an integrator parameter, e.g. accuracy=2 (repeatable)")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        print(json.dumps(measure(args.scenes[0], args.child, *args.resolution, args.spp, parse_params(args.param))))
        return 0
    print(f"{args.resolution[0]}x{args.resolution[1]}, {args.spp} spp, parameters {parse_params(args.param) or 'default'}")
    print(f"{'scene':<20} {'integrator':<24} {'records':>8} {'preprocess s':>12} {'render s':>9} {'peak MiB':>9} "
          f"{'+MiB':>6} {'cache MiB':>9}  limit")
    status = 0
    for scene in args.scenes:
        for integrator in args.integrators.split(","):
            r = run_child(scene, integrator, args)
            name = Path(r["scene"]).name
            if "error" in r:
                print(f"{name:<20} {integrator:<24} error: {r['error']}")
                status = 1
                continue
            limit = LIMIT_MB.get(name)
            verdict = "" if limit is None else (f"< {limit} MiB " + ("met" if r["peak_mb"] < limit else "MISSED"))
            if limit is not None and r["peak_mb"] >= limit:
                status = 1
            print(f"{name:<20} {integrator:<24} {r['records']:>8} {r['preprocess_s']:>12.2f} {r['render_s']:>9.2f} "
                  f"{r['peak_mb']:>9.0f} {r['added_mb']:>6.0f} {r['cache_mb']:>9.1f}  {verdict}", flush=True)
    return status


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT / "python"))  # this checkout's gi
    sys.exit(main())
