"""How well `auto`'s pilots see each cache technique's bias and noise, against measured truth.

For one scene: path-traced references at a coarse resolution of about 1,024 pixels (where the
pilots rendered until they became tiles of the render's own pixels, renderer/auto_select.h; the
coarse columns show what that cost) and at the render's, then for each technique with a cache
(irradiance records or photon maps) its bias at both resolutions: two long renders with two seeds,
the squared error of their mean against the reference, less both images' noise (each pair's
squared difference / 4). At the pilots' resolution it is measured twice: with the render's photon
counts and with the counts the pilots use (scaled with the pixels). Then --repeats runs of the
pilots themselves (`auto` with --horizon seconds of pilot time: `--auto-horizon` at spp 1), whose
log gives each technique's predicted bias (the first of its three parts). Last, the camera
samples' noise per sample, at the pilots' resolution, of the photon techniques against their
photon counts (one photon map: its first samples against all of them), since the pilots trace
fewer photons than the render, and the law in the photon count the pilots fit to it
(renderer/auto_select.h).
All in sRGB codes squared; one run on a shared machine.

    .venv/bin/python bench/pilot_accuracy.py [--scene cornell|room-sky|sponza|sibenik|sibenik-windows|FILE]
        [--resolution 160 120]
        [--reference-seconds 240] [--seconds 30] [--repeats 3] [--horizon 60]
"""
import argparse
import re
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
SCENES = {"cornell": ROOT / "scenes/cornell/cornell.usda",
          "room-sky": ROOT / "scenes/window_room/window_room_sky.usda",
          "sponza": ROOT / "scenes/sponza/sponza.usda",
          "sibenik": ROOT / "scenes/sibenik/sibenik_sky.usda",
          "sibenik-windows": ROOT / "scenes/sibenik/sibenik.usda"}
CACHES = ["irradianceCache", "adaptiveIrradianceCache", "photonMapIrradianceCache", "photonMapFinalGather"]
PHOTON_PARAMS = ("photons", "causticPhotons", "photonsPerPass")


def codes(img):
    from gi import metrics
    return metrics.srgb8(img).astype(np.float64)


def main():
    from gi import _core
    from gi.loader import load_stage
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="cornell")
    parser.add_argument("--resolution", type=int, nargs=2, default=(160, 120))
    parser.add_argument("--reference-seconds", type=float, default=240.0)
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--horizon", type=float, default=60.0)
    args = parser.parse_args()
    path = SCENES.get(args.scene, Path(args.scene))
    loaded = load_stage(str(path))
    width, height = args.resolution
    scale = max(1.0, (width * height / 1024) ** 0.5)
    pilot = (max(1, round(width / scale)), max(1, round(height / scale)))
    share = pilot[0] * pilot[1] / (width * height)
    defaults = {i["name"]: {p["name"]: p["default"] for p in i["params"]} for i in _core.integrators()}

    def render(integrator, size, seconds=0.0, seed=1, spp=1 << 24, params=None):
        s = _core.RenderSettings()
        s.width, s.height = size
        s.integrator, s.spp, s.seed, s.time_limit = integrator, spp, seed, seconds
        s.params = params or {}
        return _core.render(loaded.scene, s)

    def pilot_photons(integrator):
        d = defaults[integrator]
        return {k: int(min(d[k], max(2000, round(d[k] * share)))) for k in PHOTON_PARAMS if k in d}

    def pair(integrator, size, seconds, params=None, seed=1):
        a = np.asarray(render(integrator, size, seconds, seed, params=params).color, dtype=np.float64)
        b = np.asarray(render(integrator, size, seconds, seed + 1, params=params).color, dtype=np.float64)
        return (a + b) / 2, float(np.mean((codes(a) - codes(b)) ** 2)) / 4

    print(f"# {path.name}: pilots {pilot[0]}x{pilot[1]}, render {width}x{height}; sRGB codes squared\n")
    references = {}
    for size, seconds in [(pilot, args.reference_seconds / 4), (tuple(args.resolution), args.reference_seconds)]:
        references[size] = pair("path", size, seconds / 2, seed=1000)
        print(f"reference {size[0]}x{size[1]}: path, 2 x {seconds / 2:.0f} s, its noise {references[size][1]:.3f}")
    print("\n| technique | bias, pilots' size, render's photons | same, pilots' photons | bias, render's size | "
          "pilots' estimate (each run) |")
    print("|---|---|---|---|---|")
    estimates = {t: [] for t in CACHES}
    for repeat in range(args.repeats):
        result = render("auto", tuple(args.resolution), seed=10 + repeat, spp=1,
                        params={"autoHorizon": args.horizon})
        for t in CACHES:
            m = re.search(rf" {t} [0-9.]+ \(([0-9.]+) \+", result.auto_summary)
            estimates[t].append(float(m.group(1)) if m else float("nan"))
    for t in CACHES:
        row = []
        variants = [(pilot, None), (pilot, pilot_photons(t)), (tuple(args.resolution), None)]
        for size, params in variants:
            seconds = args.seconds / 4 if size == pilot else args.seconds
            mean, noise = pair(t, size, seconds, params)
            ref, ref_noise = references[size]
            row.append(float(np.mean((codes(mean) - codes(ref)) ** 2)) - noise - ref_noise)
        print(f"| {t} | {row[0]:.2f} | {row[1]:.2f} | {row[2]:.2f} | "
              f"{', '.join(f'{e:.2f}' for e in estimates[t])} |", flush=True)

    print(f"\nNoise per camera sample at {pilot[0]}x{pilot[1]} against photon count (the pilots' count first), "
          "one photon map each: the squared difference of its first 1/4 of the samples and all of them, "
          "x samples, 3 seeds; the law a + b x (x = the render's photons / the map's) through the first two:")
    print("| technique | photons | noise x samples | a + b x | preprocessing |")
    print("|---|---|---|---|---|")
    for t, spp in [("photonMapFinalGather", 64), ("photonMapIrradianceCache", 256)]:
        full = defaults[t]["photons"]
        counts = sorted({pilot_photons(t)["photons"], full // 4, full})
        measured = []
        for photons in counts:
            params = {k: photons for k in ("photons", "causticPhotons")}
            noise, pre = [], []
            for seed in range(100, 103):
                # The same seed traces the same photon map: the first spp / 4 samples are the
                # full render's first, so their difference is camera samples' noise alone (the
                # photon cache's records also grow with the samples: for it, an upper bound).
                few = render(t, pilot, seed=seed, spp=spp // 4, params=params)
                many = render(t, pilot, seed=seed, spp=spp, params=params)
                d = codes(np.asarray(few.color, dtype=np.float64)) - codes(np.asarray(many.color, dtype=np.float64))
                noise.append(float(np.mean(d ** 2)) / (4 / spp - 1 / spp))
                pre.append(many.stats["preprocess_seconds"])
            measured.append(np.mean(noise))
            x = [full / c for c in counts]
            law = ""
            if len(measured) >= 2:
                b = (measured[0] - measured[1]) / (x[0] - x[1])
                a = measured[1] - b * x[1]
                law = f"{a + b * full / photons:.0f}" if b > 0 and a >= 0 else ""
            print(f"| {t} | {photons} | {measured[-1]:.0f} | {law} | {np.mean(pre):.2f} s |", flush=True)

if __name__ == "__main__":
    main()
