"""`--integrator auto` against every technique at the same time limit, per scene and budget.

For each scene: a reference (the path tracer at unbounded depth for --reference-seconds; where a
sun is seen only through glass, the path tracer without the sun plus the progressive photon map of
the sun alone, bench/references.py; --glass-reference names one integrator instead), then
at each budget T, in rounds: every technique at its defaults with time limit T (seed = the round,
1, 2, ...) and `auto` with time limit T (its pilots included; seeds 1, 11, 21, ...). A technique's
error is the mean over its --seeds renders: one render's RMSE varies between seeds and with the
machine's speed over minutes (on Sponza at 10 s the adaptive cache gave 4.95, 5.09 and 5.03 codes
in three seeds, the path tracer 5.83, 5.75 and 5.74, and one render each earlier that day 4.67 and 5.43),
and the least of six single renders is a lucky draw, which no choice can match on average. The
rounds interleave the techniques and auto so that all see the machine alike.

Printed per scene and budget: each run's measured seconds, RMSE on sRGB8 and mean FLIP against
the reference, auto's choice and pilot seconds, and auto's error over the best technique's mean
(the issue's goal: at most 1.10, in both metrics) and over the path tracer's mean (at most 1.00);
the measure proposed in README (within 1.10 of the best in RMSE, at most sqrt(1 / (1 - pilot
share)) = 1.054 of the path tracer's) beside it; and what the pilots predicted for each technique
(RMSE and samples per pixel, from auto's log) beside what its own renders reached. Figures are from
one run on a shared machine: compare within a table.

    .venv/bin/python bench/auto.py [--scenes cornell,room,room-sky,sponza,sibenik,sibenik-portals,sibenik-windows]
        [--budgets 10,60] [--resolution 160 120] [--reference-seconds 120] [--seeds 2] [--auto-runs 2]
"""
import argparse
import re
import time
from pathlib import Path

import numpy as np

import references

ROOT = Path(__file__).resolve().parent.parent

# name -> (scene, whether its sun reaches the view only through glass). Neither single technique
# is a sure reference there: the path tracer misses much of the sun through the glass, and a photon
# map of the sky carries its own bias (with portals it also leaves out light that no portal covers):
# README, "A reference per light".
SCENES = {"cornell": (ROOT / "scenes/cornell/cornell.usda", False),
          "room": (ROOT / "scenes/window_room/window_room.usda", True),
          "room-sky": (ROOT / "scenes/window_room/window_room_sky.usda", False),
          "sponza": (ROOT / "scenes/sponza/sponza.usda", False),
          "sibenik": (ROOT / "scenes/sibenik/sibenik_sky.usda", True),
          "sibenik-windows": (ROOT / "scenes/sibenik/sibenik.usda", True),
          "sibenik-portals": (ROOT / "scenes/sibenik/sibenik_sky_portals.usda", True)}
GOAL_OVER_BEST, GOAL_OVER_PATH = 1.10, 1.00


def proposed_over_path():
    """README's proposed bound on auto's RMSE over the path tracer's: what the pilots' default share
    of T costs an unbiased technique, sqrt(1 / (1 - share)) (1.054 at 0.1). This bench once used
    1.05, which a run that rightly takes the path tracer misses by its pilots alone."""
    from gi import _core
    auto = next(i for i in _core.integrators() if i["name"] == "auto")
    share = next(p["default"] for p in auto["params"] if p["name"] == "autoPilotShare")
    return 1 / np.sqrt(1 - share)


def render(loaded, integrator, resolution, seconds, seed=1):
    from gi import _core
    s = _core.RenderSettings()
    s.width, s.height = resolution
    s.integrator, s.spp, s.seed, s.time_limit = integrator, 1 << 24, seed, seconds
    start = time.perf_counter()
    result = _core.render(loaded.scene, s)
    wall = time.perf_counter() - start
    # The metrics show NaN as black: a non-finite image must be caught here, not hidden in RMSE.
    if not np.isfinite(np.asarray(result.color)).all():
        raise SystemExit(f"{integrator} (seed {seed}, {seconds:g} s) rendered NaN or Inf pixels")
    return result, wall


def predictions(summary):
    """{technique: (predicted RMSE, predicted samples per pixel or None)} from auto's log line."""
    found = {}
    for m in re.finditer(r" (\w+) ([0-9.]+) \(([^()]*)\)", summary):
        spp = re.search(r"; ([0-9]+) spp$", m.group(3))
        found[m.group(1)] = (float(m.group(2)), int(spp.group(1)) if spp else None)
    return found


def print_predictions(techniques, mean, spps, predicted, budget, pilot_seconds):
    """The pilots' predictions beside what each technique reached in its own renders at T. The
    predictions are for the time auto has left after its pilots, so a technique whose error is all
    noise reaches sqrt(T / (T - pilots)) of its prediction at T (1.054 at a 10% share), and its
    samples in T are T / (T - pilots) of those predicted, less its preprocessing's share."""
    if not any(predicted.values()):
        return
    share = float(np.mean(pilot_seconds)) / budget if pilot_seconds else 0.0
    print(f"\nPredicted by the pilots (for T less their {share:.0%}) against reached at T:")
    print("| technique | spp reached (mean) | spp predicted | RMSE reached (mean) | RMSE predicted | predicted / reached RMSE |")
    print("|---|---|---|---|---|---|")
    for t in techniques:
        if not predicted[t]:
            continue
        rmse = ", ".join(f"{p[0]:.2f}" for p in predicted[t])
        spp = ", ".join("-" if p[1] is None else str(p[1]) for p in predicted[t])
        ratios = ", ".join(f"{p[0] / mean[t][0]:.2f}" for p in predicted[t])
        print(f"| {t} | {np.mean(spps[t]):.0f} | {spp} | {mean[t][0]:.2f} | {rmse} | {ratios} |")


def main():
    from gi import _core, metrics
    from gi.loader import load_stage
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--budgets", default="10,60")
    parser.add_argument("--resolution", type=int, nargs=2, default=(160, 120))
    parser.add_argument("--reference-seconds", type=float, default=120.0)
    parser.add_argument("--glass-reference", default="per-light",
                        help="per-light (bench/references.py) or an integrator's name")
    parser.add_argument("--seeds", type=int, default=2, help="renders per technique (seeds 1, 2, ...)")
    parser.add_argument("--auto-runs", type=int, default=2, help="auto renders per scene and budget")
    args = parser.parse_args()
    if args.seeds < 1:
        parser.error("--seeds must be at least 1: the ratios are against the techniques' mean errors")
    resolution = tuple(args.resolution)
    techniques = list(_core.auto_candidates())
    summary = []
    for name in args.scenes.split(","):
        path, glass = SCENES[name]
        loaded = load_stage(str(path))
        def render_image(stage_loaded, integrator, seconds, seed):
            result, wall = render(stage_loaded, integrator, resolution, seconds, seed=seed)
            return np.asarray(result.color), result.spp, wall
        reference, described = references.reference(path, glass, args.glass_reference, args.reference_seconds,
                                                    render_image)
        for budget in [float(b) for b in args.budgets.split(",")]:
            print(f"\n## {name} ({path.name}), {resolution[0]}x{resolution[1]}, T = {budget:g} s: reference "
                  f"{described}")
            print("| run | seed | seconds | spp | RMSE sRGB8 | FLIP |")
            print("|---|---|---|---|---|---|")
            errors = {t: [] for t in techniques}
            walls = {t: [] for t in techniques}
            spps = {t: [] for t in techniques}
            predicted = {t: [] for t in techniques}  # (RMSE, spp) per auto run, from its log
            autos = []  # (integrator, RMSE, FLIP, pilot seconds, wall)
            for round_ in range(max(args.seeds, args.auto_runs)):
                if round_ < args.seeds:
                    for integrator in techniques:
                        result, wall = render(loaded, integrator, resolution, budget, seed=1 + round_)
                        m = metrics.compare(np.asarray(result.color), reference)
                        errors[integrator].append((m.rmse_srgb8, m.flip))
                        walls[integrator].append(wall)
                        spps[integrator].append(result.spp)
                        print(f"| {integrator} | {1 + round_} | {wall:.1f} | {result.spp} | {m.rmse_srgb8:.2f} | "
                              f"{m.flip:.4f} |", flush=True)
                if round_ < args.auto_runs:  # seeds 1, 11, 21, ...: pilots and render differ
                    result, wall = render(loaded, "auto", resolution, budget, seed=1 + 10 * round_)
                    m = metrics.compare(np.asarray(result.color), reference)
                    autos.append((result.integrator, m.rmse_srgb8, m.flip, result.stats["auto_pilot_seconds"], wall))
                    for t, p in predictions(result.auto_summary).items():
                        predicted[t].append(p)
                    print(f"| auto -> {result.integrator} | {1 + 10 * round_} | {wall:.1f} | {result.spp} | "
                          f"{m.rmse_srgb8:.2f} | {m.flip:.4f} |\n\n{result.auto_summary}\n", flush=True)
            mean = {t: tuple(float(np.mean([e[i] for e in errors[t]])) for i in (0, 1)) for t in techniques}
            print("| technique | mean RMSE sRGB8 (range) | mean FLIP (range) |")
            print("|---|---|---|")
            for t in techniques:
                r, f = [e[0] for e in errors[t]], [e[1] for e in errors[t]]
                print(f"| {t} | {mean[t][0]:.2f} ({min(r):.2f}-{max(r):.2f}) | {mean[t][1]:.4f} "
                      f"({min(f):.4f}-{max(f):.4f}) |")
            print_predictions(techniques, mean, spps, predicted, budget, [a[3] for a in autos])
            best = min(techniques, key=lambda t: mean[t][0])
            best_flip = min(mean[t][1] for t in techniques)
            for chosen, rmse, flip, pilots, wall in autos:
                row = (name, budget, rmse / mean[best][0], flip / best_flip, rmse / mean["path"][0],
                       flip / mean["path"][1], chosen, best, pilots, wall, max(max(w) for w in walls.values()))
                summary.append(row)
                print(f"auto ({chosen}) / best mean: RMSE {row[2]:.2f}, FLIP {row[3]:.2f}; / path mean: RMSE "
                      f"{row[4]:.2f}, FLIP {row[5]:.2f}")
    print(f"\n## Summary (the issue's goal: auto / best <= {GOAL_OVER_BEST:.2f} and auto / path <= "
          f"{GOAL_OVER_PATH:.2f}, both metrics; proposed: RMSE / best <= {GOAL_OVER_BEST:.2f}, RMSE / path <= "
          f"{proposed_over_path():.3f}; against the techniques' means over their seeds)")
    print("| scene | T | auto chose | best (RMSE) | auto / best RMSE, FLIP | auto / path RMSE, FLIP | pilots | "
          "auto took | slowest technique took | goal met | proposed met |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, budget, rb, fb, rp, fp, chosen, best, pilots, auto_wall, slowest in summary:
        met = rb <= GOAL_OVER_BEST and fb <= GOAL_OVER_BEST and rp <= GOAL_OVER_PATH and fp <= GOAL_OVER_PATH
        proposed = rb <= GOAL_OVER_BEST and rp <= proposed_over_path()
        print(f"| {name} | {budget:g} s | {chosen} | {best} | {rb:.2f}, {fb:.2f} | {rp:.2f}, {fp:.2f} | "
              f"{pilots:.2f} s ({pilots / budget:.0%}) | {auto_wall:.1f} s | {slowest:.1f} s | {'yes' if met else 'no'} | "
              f"{'yes' if proposed else 'no'} |")


if __name__ == "__main__":
    main()
