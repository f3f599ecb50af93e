"""`--integrator auto` against every technique at the same time limit, per scene and budget.

For each scene: a reference (the path tracer at unbounded depth for --reference-seconds; where a
sun is seen only through glass, the consistent progressivePhotonMap, as in bench/untuned.py), then
at each budget T every technique at its defaults with time limit T and `auto` with time limit T
(its pilots included). Printed per scene and budget: each run's measured seconds, RMSE on sRGB8
and mean FLIP against the reference, auto's choice and pilot seconds, and auto's error over the
best single technique's (the goal: at most 1.10, in both metrics) and over the path tracer's (at
most 1.00). Figures are from one run on a shared machine: compare within a table.

    .venv/bin/python bench/auto.py [--scenes cornell,room,room-sky,sponza,sibenik,sibenik-portals,sibenik-windows]
        [--budgets 10,60] [--resolution 160 120] [--reference-seconds 120] [--auto-runs 1]
"""
import argparse
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

# name -> (scene, whether its light reaches the view only through glass)
SCENES = {"cornell": (ROOT / "scenes/cornell/cornell.usda", False),
          "room": (ROOT / "scenes/window_room/window_room.usda", True),
          "room-sky": (ROOT / "scenes/window_room/window_room_sky.usda", False),
          "sponza": (ROOT / "scenes/sponza/sponza.usda", False),
          "sibenik": (ROOT / "scenes/sibenik/sibenik_sky.usda", True),
          "sibenik-windows": (ROOT / "scenes/sibenik/sibenik.usda", True),
          "sibenik-portals": (ROOT / "scenes/sibenik/sibenik_sky_portals.usda", True)}
GOAL_OVER_BEST, GOAL_OVER_PATH = 1.10, 1.00


def render(loaded, integrator, resolution, seconds, seed=1):
    from gi import _core
    s = _core.RenderSettings()
    s.width, s.height = resolution
    s.integrator, s.spp, s.seed, s.time_limit = integrator, 1 << 24, seed, seconds
    start = time.perf_counter()
    result = _core.render(loaded.scene, s)
    return result, time.perf_counter() - start


def main():
    from gi import _core, metrics
    from gi.loader import load_stage
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--budgets", default="10,60")
    parser.add_argument("--resolution", type=int, nargs=2, default=(160, 120))
    parser.add_argument("--reference-seconds", type=float, default=120.0)
    parser.add_argument("--glass-reference", default="progressivePhotonMap")
    parser.add_argument("--auto-runs", type=int, default=1, help="auto renders per scene and budget")
    args = parser.parse_args()
    resolution = tuple(args.resolution)
    techniques = list(_core.auto_candidates())
    summary = []
    for name in args.scenes.split(","):
        path, glass = SCENES[name]
        loaded = load_stage(str(path))
        ref_integrator = args.glass_reference if glass else "path"
        ref, ref_wall = render(loaded, ref_integrator, resolution, args.reference_seconds, seed=1000)
        reference = np.asarray(ref.color)
        for budget in [float(b) for b in args.budgets.split(",")]:
            print(f"\n## {name} ({path.name}), {resolution[0]}x{resolution[1]}, T = {budget:g} s: reference "
                  f"{ref_integrator} {ref.spp} spp in {ref_wall:.0f} s")
            print("| technique | seconds | spp | RMSE sRGB8 | FLIP |")
            print("|---|---|---|---|---|")
            errors, walls = {}, {}
            for integrator in techniques:
                result, wall = render(loaded, integrator, resolution, budget)
                m = metrics.compare(np.asarray(result.color), reference)
                errors[integrator] = (m.rmse_srgb8, m.flip)
                walls[integrator] = wall
                print(f"| {integrator} | {wall:.1f} | {result.spp} | {m.rmse_srgb8:.2f} | {m.flip:.4f} |", flush=True)
            best = min(techniques, key=lambda t: errors[t][0])
            best_rmse = errors[best][0]
            best_flip = min(errors[t][1] for t in techniques)
            for run in range(args.auto_runs):  # seeds 1, 11, 21, ...: pilots and render differ
                result, wall = render(loaded, "auto", resolution, budget, seed=1 + 10 * run)
                m = metrics.compare(np.asarray(result.color), reference)
                print(f"| auto -> {result.integrator} | {wall:.1f} | {result.spp} | {m.rmse_srgb8:.2f} | "
                      f"{m.flip:.4f} |\n\n{result.auto_summary}\n", flush=True)
                row = (name, budget, m.rmse_srgb8 / best_rmse, m.flip / best_flip,
                       m.rmse_srgb8 / errors["path"][0], m.flip / errors["path"][1], result.integrator, best,
                       result.stats["auto_pilot_seconds"], wall, max(walls[t] for t in techniques))
                summary.append(row)
                print(f"auto / best: RMSE {row[2]:.2f}, FLIP {row[3]:.2f}; auto / path: RMSE {row[4]:.2f}, "
                      f"FLIP {row[5]:.2f}")
    print(f"\n## Summary (goal: auto / best <= {GOAL_OVER_BEST:.2f} and auto / path <= {GOAL_OVER_PATH:.2f})")
    print("| scene | T | auto chose | best (RMSE) | auto / best RMSE, FLIP | auto / path RMSE, FLIP | pilots | "
          "auto took | slowest technique took | goal met |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, budget, rb, fb, rp, fp, chosen, best, pilots, auto_wall, slowest in summary:
        met = rb <= GOAL_OVER_BEST and fb <= GOAL_OVER_BEST and rp <= GOAL_OVER_PATH and fp <= GOAL_OVER_PATH
        print(f"| {name} | {budget:g} s | {chosen} | {best} | {rb:.2f}, {fb:.2f} | {rp:.2f}, {fp:.2f} | "
              f"{pilots:.2f} s ({pilots / budget:.0%}) | {auto_wall:.1f} s | {slowest:.1f} s | {'yes' if met else 'no'} |")


if __name__ == "__main__":
    main()
