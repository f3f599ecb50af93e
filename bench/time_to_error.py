"""Time to reach a fixed RMSE against a reference, per integrator, with ratios to the path tracer.

Each integrator renders the scene with its default parameters at doubling samples per pixel (1, 2,
4, ...), each level a fresh render, until its RMSE against the reference falls to the target or its
time runs out. The time to the target is interpolated log-log between the two levels that bracket it
(error falls as a power of time for unbiased techniques). Biased techniques level off at their bias
and may never reach the target: the table then says so and shows their best error.

All figures come from this one run (machines are shared and noisy, so only the ratios to the path
tracer are meaningful).

    .venv/bin/python bench/time_to_error.py [SCENE] --reference ref.exr [--target 8] [--metric srgb8]
        [--integrators path,direct] [--max-seconds 60] [--threads N]
    .venv/bin/python bench/time_to_error.py [SCENE] --resolution 128 128 --reference-seconds 60

Without --reference, one is rendered first (gi.reference, for --reference-seconds) at --resolution.
The target must lie above the reference's own noise, or nothing reaches it.
"""
import argparse
import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_TARGETS = {"srgb8": 8.0, "linear": 0.02}   # RMSE on 0..255 codes / on linear radiance


def error_function(metric):
    from gi import metrics
    return {"srgb8": metrics.rmse_srgb8, "linear": metrics.rmse_linear}[metric]


def make_reference(scene, resolution, seconds, threads):
    """A reference rendered in this run: the path tracer for `seconds` (the error target is out of
    reach on purpose, so the time decides)."""
    from gi.reference import render_reference
    reference = render_reference(str(scene), max_seconds=seconds, target_error=1e-12, resolution=resolution,
                                 threads=threads)
    print(f"reference: {reference.spp} spp in {reference.seconds:.1f} s, pixel relative standard error "
          f"{reference.pixel_relative_standard_error:.3g}")
    return reference.color, reference.camera_path


def load_reference(path):
    from gi.study import load_reference as load
    color, meta = load(path)
    return color, meta.get("gi:camera") or None


def error_curve(loaded, integrator, reference, error_of, target, max_seconds, threads):
    """[(spp, seconds, error)] at doubling spp until the error reaches target or time runs out."""
    from gi.render import render_loaded, render_settings
    height, width = reference.shape[:2]
    curve, spent, spp = [], 0.0, 1
    while True:
        settings = render_settings(loaded, integrator, {}, spp, 0, threads, 0.0, (width, height), "box")
        result = render_loaded(loaded, settings, integrator)
        seconds = result.stats["seconds"]
        curve.append((spp, seconds, error_of(result.color, reference)))
        spent += seconds
        # The next level takes about twice as long as this one: stop if that would overrun.
        if curve[-1][2] <= target or spent + 2 * seconds > max_seconds:
            return curve
        spp *= 2


def time_to_target(curve, target):
    """(seconds, spp) at which the error reaches target, log-log interpolated; None if it never does."""
    for index, (spp, seconds, error) in enumerate(curve):
        if error > target:
            continue
        if index == 0 or error <= 0:
            return seconds, spp   # reached at the first level: an upper bound
        spp0, seconds0, error0 = curve[index - 1]
        slope = (math.log(seconds) - math.log(seconds0)) / (math.log(error) - math.log(error0))
        interpolated = math.exp(math.log(seconds0) + slope * (math.log(target) - math.log(error0)))
        return interpolated, spp
    return None


def measure(scene, reference, camera, integrators, metric, target, max_seconds, threads):
    import gi
    loaded = gi.load_stage(str(scene), camera=camera)
    error_of = error_function(metric)
    rows = []
    for name in integrators:
        start = time.perf_counter()
        curve = error_curve(loaded, name, reference, error_of, target, max_seconds, threads)
        reached = time_to_target(curve, target)
        rows.append({"integrator": name, "reached": reached, "best": min(e for _, _, e in curve),
                     "levels": len(curve), "wall": time.perf_counter() - start})
    return rows


def print_table(rows, metric, target):
    path_time = next((r["reached"][0] for r in rows if r["integrator"] == "path" and r["reached"]), None)
    print(f"\ntime to RMSE {metric} <= {target:g}")
    print(f"{'integrator':<26} {'seconds':>9} {'spp':>7} {'x path':>7} {'best RMSE':>10} {'levels':>6}")
    for r in rows:
        if r["reached"]:
            seconds, spp = r["reached"]
            ratio = f"{seconds / path_time:7.2f}" if path_time else f"{'-':>7}"
            print(f"{r['integrator']:<26} {seconds:>9.3f} {spp:>7} {ratio} {r['best']:>10.4g} {r['levels']:>6}")
        else:
            print(f"{r['integrator']:<26} {'not reached':>9} {'':>7} {'-':>7} {r['best']:>10.4g} {r['levels']:>6}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", nargs="?", type=Path, default=ROOT / "scenes/cornell/cornell.usda")
    parser.add_argument("--reference", type=Path, help="reference EXR (default: render one now)")
    parser.add_argument("--reference-seconds", type=float, default=60.0)
    parser.add_argument("--resolution", type=int, nargs=2, default=[128, 128],
                        help="for a reference rendered now (a given reference sets the size)")
    parser.add_argument("--metric", choices=sorted(DEFAULT_TARGETS), default="srgb8")
    parser.add_argument("--target", type=float, help="RMSE to reach (default 8 for srgb8, 0.02 for linear)")
    parser.add_argument("--integrators", help="comma-separated (default: every integrator in _core.integrators())")
    parser.add_argument("--max-seconds", type=float, default=60.0, help="render time per integrator")
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args(argv)

    from gi import _core
    integrators = args.integrators.split(",") if args.integrators else [i["name"] for i in _core.integrators()]
    target = args.target if args.target is not None else DEFAULT_TARGETS[args.metric]
    if args.reference:
        reference, camera = load_reference(args.reference)
    else:
        reference, camera = make_reference(args.scene, tuple(args.resolution), args.reference_seconds, args.threads)
    rows = measure(args.scene, reference, camera, integrators, args.metric, target, args.max_seconds, args.threads)
    print_table(rows, args.metric, target)
    return 0


if __name__ == "__main__":
    sys.exit(main())
