"""The path tracer's time to a fixed error on a window-lit interior, with and without a portal.

The glazed-window room under its sky with the pane removed, so that shadow rays see the sky through
the opening (through glass, all skylight is a caustic, which no light sampling reaches):
scenes/window_room/window_room_open.usda, and the same with a UsdLux portal over the opening
(window_room_open_portal.usda). Each renders at
doubling samples per pixel until its RMSE against a long path-traced reference (of the scene
without the portal) falls below the target; the time to the target is interpolated log-log
between the two levels that bracket it. Figures are from one run: read the ratio.

    .venv/bin/python bench/portals.py [--resolution 128 96] [--target 0.004] [--reference-spp 8192]
"""
import argparse
import math
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
ROOMS = ROOT / "scenes" / "window_room"


def render(loaded, resolution, spp, seed):
    from gi import _core
    s = _core.RenderSettings()
    s.width, s.height = resolution
    s.integrator, s.spp, s.seed = "path", spp, seed
    start = time.perf_counter()
    result = _core.render(loaded.scene, s)
    return np.asarray(result.color), time.perf_counter() - start


def time_to_error(loaded, reference, resolution, target):
    previous = None
    spp = 1
    while spp <= 1 << 16:
        image, seconds = render(loaded, resolution, spp, seed=7)
        error = float(np.sqrt(np.mean((image - reference) ** 2)))
        if error <= target:
            if previous is None:
                return seconds, spp
            (t0, e0) = previous
            # log-log interpolation between the bracketing levels
            f = (math.log(e0) - math.log(target)) / (math.log(e0) - math.log(error))
            return math.exp(math.log(t0) + f * (math.log(seconds) - math.log(t0))), spp
        previous = (seconds, error)
        spp *= 2
    return math.inf, spp


def main():
    from gi.loader import load_stage
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", type=int, nargs=2, default=(128, 96))
    parser.add_argument("--target", type=float, default=0.004, help="RMSE on linear radiance")
    parser.add_argument("--reference-spp", type=int, default=8192)
    args = parser.parse_args()
    resolution = tuple(args.resolution)
    plain = load_stage(str(ROOMS / "window_room_open.usda"))
    portal = load_stage(str(ROOMS / "window_room_open_portal.usda"))
    reference, ref_seconds = render(plain, resolution, args.reference_spp, seed=1000)
    print(f"reference: {args.reference_spp} spp in {ref_seconds:.0f} s, mean {reference.mean():.5f}")
    results = {}
    for name, loaded in (("without portal", plain), ("with portal", portal)):
        seconds, spp = time_to_error(loaded, reference, resolution, args.target)
        results[name] = seconds
        print(f"{name}: RMSE {args.target} in {seconds:.2f} s (reached at {spp} spp)")
    print(f"speed-up: {results['without portal'] / results['with portal']:.1f}x")


if __name__ == "__main__":
    main()
