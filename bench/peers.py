"""gi against Mitsuba 3 (issue 17): the same scenes, converted from the arrays gi's loader reads
(bench/mitsuba_scene.py), rendered by both path tracers in one run, alternately, with the same
thread count.

Per scene:
1. Agreement: each renderer renders two independent images (different seeds) for --converge-seconds
   in all. The two renderers agree when their image means are within 1% and the RMSE between them
   is at the noise floor: the RMSE expected between two independent images of these noise levels,
   sqrt((RMSE(gi seed 1, gi seed 2)^2 + RMSE(mi seed 1, mi seed 2)^2) / 2).
   The reference for step 2 is the mean of the two renderers' means.
2. Equal time (--seconds each): camera samples per second, RMSE on 8-bit sRGB and mean FLIP against
   the reference, and the efficiency 1 / (MSE_sRGB8 * t), for gi's path tracer, Mitsuba's path
   tracer and gi's --best technique. gi renders once with its time limit (which counts its
   preprocessing: the photon passes of --best); Mitsuba renders batches of about t/8 until t has
   passed. Ratios are gi over Mitsuba, by wall time and by process CPU time. This is repeated
   --rounds times (3); each round's ratios are printed, and their median is the figure to quote:
   on a shared machine one round's ratio moved by up to a tenth against the next.

Times are render times only: scene load and acceleration-structure build are excluded for both
(and printed), and Mitsuba's kernels are compiled by a 1-spp warm-up render first. The machine is
shared: figures are from one run, alternating the renderers so that load changes hit both.

    .venv/bin/pip install -e '.[bench]'      # Mitsuba 3 (the `bench` extra)
    .venv/bin/python bench/peers.py [--scenes cornell,sponza,sibenik] [--width 128]
        [--converge-seconds 120] [--seconds 10] [--rounds 3] [--threads 2] [--best progressivePhotonMap]
        [--mitsuba-variant scalar_rgb] [--tracing-only]

--mitsuba-variant scalar_rgb runs Mitsuba one path at a time, as gi does: what its vectorised
LLVM variant gains over its own scalar code. Only for scenes without the specular-workflow BSDF
(the Cornell box): that BSDF is Python (mitsuba_scene.py), which the LLVM variant compiles into
its kernel once and the scalar variant would call per sample.

--tracing-only compares the two renderers' ray casting alone (see tracing_rates).
"""
import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
import mitsuba_scene  # noqa: E402  (bench/, next to this file)

SCENES = {"cornell": ROOT / "scenes/cornell/cornell.usda",
          "sponza": ROOT / "scenes/sponza/sponza.usda",
          "sibenik": ROOT / "scenes/sibenik/sibenik_sky.usda"}


class Clock:
    """Wall seconds and process CPU seconds (all threads) of a block. On a loaded machine the CPU
    time is the fairer cost: a renderer that runs more threads than asked gets more of the cores."""

    def __enter__(self):
        self.wall, self.cpu = time.perf_counter(), time.process_time()
        return self

    def __exit__(self, *exc):
        self.wall, self.cpu = time.perf_counter() - self.wall, time.process_time() - self.cpu
        return False


class Gi:
    name = "gi"

    def __init__(self, path, resolution, threads, converted_normals=False):
        import gi
        start = time.perf_counter()
        self.loaded = gi.load_stage(str(path))
        if converted_normals:  # the meshes as the Mitsuba scene has them (see mitsuba_scene.with_converted_normals)
            self.name = "gi (Mitsuba's normals)"
            recorded, _ = mitsuba_scene.record(path)
            self.loaded.scene = mitsuba_scene.gi_scene(mitsuba_scene.with_converted_normals(recorded))
        self.loaded.scene.commit()
        self.build_seconds = time.perf_counter() - start
        self.resolution, self.threads = resolution, threads

    def render(self, spp, seed, integrator="path"):
        from gi.render import render_loaded, render_settings
        settings = render_settings(self.loaded, integrator, {}, spp, seed, self.threads, 0.0, self.resolution, "box")
        with Clock() as clock:
            result = render_loaded(self.loaded, settings, integrator)
            color = np.asarray(result.color, np.float32)[..., :3]
        return color, clock


    def render_for(self, seconds, integrator, seconds_per_sample, seed):
        """One render cut off by gi's own time limit: (image, Clock, camera samples)."""
        from gi.render import render_loaded, render_settings
        settings = render_settings(self.loaded, integrator, {}, 1 << 20, seed, self.threads, seconds, self.resolution,
                                   "box")
        with Clock() as clock:
            result = render_loaded(self.loaded, settings, integrator)
            color = np.asarray(result.color, np.float32)[..., :3]
        return color, clock, int(result.stats["camera_samples"])


class Mitsuba:
    name = "mitsuba"

    def __init__(self, path, resolution, threads):
        start = time.perf_counter()
        recorded, _ = mitsuba_scene.record(path)
        self.scene, self.approximated = mitsuba_scene.mitsuba_scene(recorded, resolution)
        self.build_seconds = time.perf_counter() - start
        self.threads, self.pixels = threads, resolution[0] * resolution[1]

    def render(self, spp, seed, integrator="path"):
        with Clock() as clock:
            image, _ = mitsuba_scene.render(self.scene, spp, seed, self.threads)
        return image, clock

    def render_for(self, seconds, integrator, seconds_per_sample, seed):
        """Renders of about seconds / 8 each (seeds from `seed` on) until `seconds` have passed;
        their spp-weighted mean: (image, Clock, camera samples)."""
        batch = spp_for(seconds / 8, seconds_per_sample)
        total, spp = None, 0
        with Clock() as clock:
            while time.perf_counter() - clock.wall < seconds:   # clock.wall: the start, until the block ends
                image, _ = mitsuba_scene.render(self.scene, batch, seed, self.threads)
                total = image * batch if total is None else total + image * batch
                spp, seed = spp + batch, seed + 1
        return total / spp, clock, spp * self.pixels


def resolution_of(path, width):
    from gi.loader import load_stage
    from gi.descriptors import CountingScene
    w, h = load_stage(str(path), scene=CountingScene()).resolution
    return width, max(1, round(width * h / w))


def spp_for(seconds, seconds_per_sample):
    return max(1, int(round(seconds / seconds_per_sample)))


def calibrate(renderer, integrator="path", least_seconds=1.0):
    """Seconds per sample per pixel, from the first of doubling renders that takes least_seconds
    (after a 1-spp warm-up: Mitsuba compiles its kernels, gi builds what it builds lazily)."""
    renderer.render(1, 999, integrator)
    spp = 1
    while True:
        _, clock = renderer.render(spp, 998, integrator)
        if clock.wall >= least_seconds:
            return clock.wall / spp
        spp *= 2


def mean_luminance(image):
    from gi import metrics
    return float(metrics.luminance(image).mean())


def agreement(renderers, per_sample, converge_seconds):
    """Two images per renderer, alternating; returns (reference, figures)."""
    from gi import metrics
    images = {r.name: [] for r in renderers}
    per_sample = dict(zip((r.name for r in renderers), per_sample.values()))
    spp = {r.name: spp_for(converge_seconds / 2, per_sample[r.name]) for r in renderers}
    for seed in (1, 2):
        for r in renderers:
            image, _ = r.render(spp[r.name], seed)
            images[r.name].append(image)
    means = {name: (a + b) / 2 for name, (a, b) in images.items()}
    ours, theirs = (r.name for r in renderers)
    floors = {name: metrics.rmse_linear(a, b) for name, (a, b) in images.items()}
    noise_floor = math.sqrt((floors[ours] ** 2 + floors[theirs] ** 2) / 2)
    cross = math.sqrt((metrics.rmse_linear(images[ours][0], images[theirs][0]) ** 2 +
                       metrics.rmse_linear(images[ours][1], images[theirs][1]) ** 2) / 2)
    figures = {"who": ours, "spp": [spp[ours], spp[theirs]],
               "mean_ratio": mean_luminance(means[ours]) / mean_luminance(means[theirs]),
               "rgb_ratio": means[ours].mean(axis=(0, 1)) / means[theirs].mean(axis=(0, 1)),
               "cross_rmse": cross, "noise_floor": noise_floor}
    return (means[ours] + means[theirs]) / 2, figures


def equal_time(renderer, integrator, seconds, per_sample, reference, resolution, seed):
    from gi import metrics
    image, clock, samples = renderer.render_for(seconds, integrator, per_sample, seed)
    rmse = metrics.rmse_srgb8(image, reference)
    spp = samples / (resolution[0] * resolution[1])
    return {"who": f"{renderer.name} {integrator}", "spp": spp, "seconds": clock.wall, "cpu_seconds": clock.cpu,
            "samples_per_second": samples / clock.wall, "samples_per_cpu_second": samples / clock.cpu,
            "rmse_srgb8": rmse, "flip": metrics.flip(image, reference),
            "efficiency": 1 / (rmse * rmse * clock.wall), "cpu_efficiency": 1 / (rmse * rmse * clock.cpu),
            "mean_ratio": mean_luminance(image) / mean_luminance(reference)}


def renderer_memory_mb(renderer, name, width, threads):
    """Resident memory (MB) one renderer adds to a fresh process: loading the scene (gi: its Scene
    with the BVH; Mitsuba: the converted scene, its kernels and libraries) and rendering 16 spp,
    over the process after it has imported gi and read the stage's settings. gi's loader runs in
    both (Mitsuba's scene is built from its arrays), so its own peak is left out of both."""
    import subprocess
    out = subprocess.run([sys.executable, __file__, "--memory-probe", renderer, "--scenes", name,
                          "--width", str(width), "--threads", str(threads),
                          "--mitsuba-variant", mitsuba_scene.VARIANT],
                         capture_output=True, text=True, check=True).stdout
    return float(out.strip().splitlines()[-1])


def resident_mb():
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2 ** 20


def probe_memory(renderer, name, width, threads):
    import gc
    path = SCENES[name]
    resolution = resolution_of(path, width)
    gc.collect()
    before = resident_mb()
    held = (Gi if renderer == "gi" else Mitsuba)(path, resolution, threads)
    held.render(16, 1)
    gc.collect()
    print(resident_mb() - before)


def run_scene(name, path, args):
    resolution = resolution_of(path, args.width)
    gi_renderer = Gi(path, resolution, args.threads)
    mi_renderer = Mitsuba(path, resolution, args.threads)
    renderers = [gi_renderer, mi_renderer]
    per_sample = {r.name: calibrate(r) for r in renderers}
    best_per_sample = calibrate(gi_renderer, args.best)
    reference, agree = agreement(renderers, per_sample, args.converge_seconds)
    agreements = [agree]
    if mi_renderer.approximated:
        # Mitsuba cannot take gi's normal rule on these triangles: gi on Mitsuba's meshes tells
        # whether the difference is that or the light transport.
        same_meshes = Gi(path, resolution, args.threads, converted_normals=True)
        agreements.append(agreement([same_meshes, mi_renderer], per_sample, args.converge_seconds / 2)[1])
    rounds = []  # each: gi's path tracer, Mitsuba's, gi's --best, rendered one after the other
    for k in range(args.rounds):  # each round its own seeds (Mitsuba's batches count up from them)
        rounds.append([equal_time(runner, integrator, args.seconds, seconds_per_sample, reference, resolution,
                                  7 + 1000 * k)
                       for runner, integrator, seconds_per_sample in ((gi_renderer, "path", per_sample["gi"]),
                                                                      (mi_renderer, "path", per_sample["mitsuba"]),
                                                                      (gi_renderer, args.best, best_per_sample))])
    memory = {who: renderer_memory_mb(who, name, args.width, args.threads) for who in ("gi", "mitsuba")}
    return {"scene": name, "resolution": resolution, "build": {r.name: r.build_seconds for r in renderers},
            "memory": memory,
            "approximated": mi_renderer.approximated, "agreements": agreements, "rounds": rounds}


def report(result):
    w, h = result["resolution"]
    print(f"\n### {result['scene']} ({w}x{h})")
    print(f"scene load + build: gi {result['build']['gi']:.1f} s, Mitsuba {result['build']['mitsuba']:.1f} s; "
          f"triangles Mitsuba shades flat or with turned normals (unlike gi): {result['approximated']}")
    print(f"resident memory a renderer adds (scene loaded, 16 spp rendered): gi {result['memory']['gi']:.0f} MB, "
          f"Mitsuba {result['memory']['mitsuba']:.0f} MB")
    for a in result["agreements"]:
        print(f"agreement, {a['who']} / Mitsuba ({a['spp'][0]} / {a['spp'][1]} spp x 2 seeds): mean luminance ratio "
              f"{a['mean_ratio']:.4f} (RGB {', '.join(f'{v:.4f}' for v in a['rgb_ratio'])}); RMSE between them "
              f"{a['cross_rmse']:.4g}, noise floor {a['noise_floor']:.4g} (ratio {a['cross_rmse'] / a['noise_floor']:.3f})")
    print("\n| round | renderer | spp | wall s | CPU s | samples/s | samples/CPU-s | mean ÷ ref | RMSE sRGB8 | FLIP "
          "| 1/(MSE·t) | 1/(MSE·CPU t) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for k, rows in enumerate(result["rounds"], 1):
        for r in rows:
            print(f"| {k} | {r['who']} | {r['spp']:.0f} | {r['seconds']:.2f} | {r['cpu_seconds']:.2f} | "
                  f"{r['samples_per_second'] / 1e3:.1f} k | {r['samples_per_cpu_second'] / 1e3:.1f} k | "
                  f"{r['mean_ratio']:.3f} | {r['rmse_srgb8']:.2f} | {r['flip']:.4f} | {r['efficiency']:.4g} | "
                  f"{r['cpu_efficiency']:.4g} |")
    # Ratios within a round, where gi and Mitsuba ran one after the other; their median over the
    # rounds is the figure to quote (the machine is shared: a round's load hits both).
    ratios = {"samples/s": [], "samples/CPU-s": [], "path efficiency": [], "path efficiency (CPU)": [],
              "best efficiency": [], "best efficiency (CPU)": [], "FLIP": []}
    for gi_path, mi_path, best in result["rounds"]:
        ratios["samples/s"].append(gi_path["samples_per_second"] / mi_path["samples_per_second"])
        ratios["samples/CPU-s"].append(gi_path["samples_per_cpu_second"] / mi_path["samples_per_cpu_second"])
        ratios["path efficiency"].append(gi_path["efficiency"] / mi_path["efficiency"])
        ratios["path efficiency (CPU)"].append(gi_path["cpu_efficiency"] / mi_path["cpu_efficiency"])
        ratios["best efficiency"].append(best["efficiency"] / mi_path["efficiency"])
        ratios["best efficiency (CPU)"].append(best["cpu_efficiency"] / mi_path["cpu_efficiency"])
        ratios["FLIP"].append(gi_path["flip"] / mi_path["flip"])
    best_name = result["rounds"][0][2]["who"]
    print(f"\ngi ÷ Mitsuba, each round (median; {best_name} for best):")
    for key, values in ratios.items():
        print(f"  {key}: {', '.join(f'{v:.2f}' for v in values)} (median {float(np.median(values)):.2f})")


def tracing_rates(name, path, rays, threads, rounds=3):
    """Closest-hit rays per CPU second through each renderer's own ray casting, the same rays:
    uniform origins in the scene's box, uniform directions, built before either clock starts.
    gi casts them through Embree one by one (as its integrators do); Mitsuba's kernel casts them
    through its own Embree as its variant does (the LLVM one in 16-wide packets). Medians of
    `rounds`, alternating."""
    import drjit as dr
    from gi import _core
    gi_renderer = Gi(path, (32, 32), threads)
    recorded, _ = mitsuba_scene.record(path)
    scene, _ = mitsuba_scene.mitsuba_scene(recorded, (32, 32))
    mi = mitsuba_scene.mitsuba()[0]
    dr.set_thread_count(threads)
    box = scene.bbox()
    lo, hi = np.array(box.min, np.float64), np.array(box.max, np.float64)
    rng = np.random.default_rng(1)
    origins = (lo + (hi - lo) * rng.random((rays, 3))).astype(np.float32)
    directions = rng.normal(size=(rays, 3))
    directions = (directions / np.linalg.norm(directions, axis=1)[:, None]).astype(np.float32)
    ray = mi.Ray3f(mi.Point3f(*(mi.Float(origins[:, k]) for k in range(3))),
                   mi.Vector3f(*(mi.Float(directions[:, k]) for k in range(3))))
    dr.eval(ray)
    dr.eval(dr.count(scene.ray_intersect_preliminary(ray).is_valid()))  # compiles the kernel
    gi_rates, mi_rates = [], []
    for _ in range(rounds):
        # gi's pool is its own (Sobol, same distribution), generated before its clock starts.
        gi_rates.append(rays / _core.embree_ray_benchmark(gi_renderer.loaded.scene, rays, 1, threads)["cpu_seconds"])
        with Clock() as clock:
            hits = dr.count(scene.ray_intersect_preliminary(ray).is_valid())
            dr.eval(hits)
            dr.sync_thread()  # with more than one thread, kernels run asynchronously
        mi_rates.append(rays / clock.cpu)
    gi_rate, mi_rate = float(np.median(gi_rates)), float(np.median(mi_rates))
    print(f"{name}: closest-hit rays per CPU second, {rays:,} rays, {threads} threads: gi {gi_rate / 1e6:.2f} M, "
          f"Mitsuba {mi_rate / 1e6:.2f} M; gi / Mitsuba {gi_rate / mi_rate:.2f}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", default="cornell,sponza,sibenik", help=f"comma-separated: {', '.join(SCENES)}")
    parser.add_argument("--width", type=int, default=128, help="image width (height keeps the scene's aspect)")
    parser.add_argument("--converge-seconds", type=float, default=120.0, help="per renderer, for the agreement")
    parser.add_argument("--seconds", type=float, default=10.0, help="equal-time budget per render")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=3,
                        help="equal-time rounds, each gi's path tracer, Mitsuba's and gi's --best in turn")
    parser.add_argument("--best", default="progressivePhotonMap", help="gi's technique set against Mitsuba's path tracer")
    parser.add_argument("--mitsuba-variant", default=mitsuba_scene.VARIANT,
                        help="Mitsuba's variant (scalar_rgb: one path at a time; see above)")
    parser.add_argument("--memory-probe", choices=["gi", "mitsuba"], help=argparse.SUPPRESS)  # the probe's process
    parser.add_argument("--memory-only", action="store_true", help="only the memory figures")
    parser.add_argument("--tracing-only", action="store_true",
                        help="only each renderer's ray casting: closest-hit rays per CPU second, the same random rays")
    args = parser.parse_args(argv)
    mitsuba_scene.VARIANT = args.mitsuba_variant
    if args.memory_probe:
        probe_memory(args.memory_probe, args.scenes, args.width, args.threads)
        return 0
    if args.memory_only:
        for name in args.scenes.split(","):
            print(name, {who: round(renderer_memory_mb(who, name, args.width, args.threads))
                         for who in ("gi", "mitsuba")}, "MB")
        return 0
    if args.tracing_only:
        for name in args.scenes.split(","):
            tracing_rates(name, SCENES[name], 1 << 21, args.threads)
        return 0
    import mitsuba
    print(f"gi against Mitsuba {mitsuba.__version__} ({mitsuba_scene.VARIANT}), {args.threads} threads, "
          f"{args.rounds} equal-time rounds in one run")
    for name in args.scenes.split(","):
        if not SCENES[name].exists():
            print(f"{name}: {SCENES[name]} missing (run scripts/import-scenes.sh); skipped")
            continue
        try:
            report(run_scene(name, SCENES[name], args))
        except mitsuba_scene.ConversionError as error:
            print(f"{name}: not converted for {mitsuba_scene.VARIANT} ({error}); skipped")
    return 0


if __name__ == "__main__":
    sys.exit(main())
