"""Writes the independent references tests/python/test_mitsuba_references.py compares gi with
(issue 19): small converged images of the Cornell box and of the analytic scenes in
tests/data/mitsuba/, rendered by Mitsuba 3's path tracer from scenes converted by
bench/mitsuba_scene.py (the arrays gi's loader reads; no gi rendering code is involved).

For each scene: <name>.exr, the mean of --batches independent renders (different seeds) of --spp
samples per pixel each, and <name>_se.exr, the per-pixel, per-channel standard error of that mean
(the batches' spread / sqrt(batches)); references.json records the spp, batch count, resolution and
the Mitsuba version. Needs the bench extra (pip install -e '.[bench]'); CI only reads the files.

    .venv/bin/python tests/data/make_mitsuba_references.py [--batches 64] [--spp 256] [--threads 2]
"""
import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
OUT = Path(__file__).resolve().parent / "mitsuba"
sys.path.insert(0, str(ROOT / "bench"))
import mitsuba_scene  # noqa: E402

# name -> the USD file; all render at their render settings' 48x48.
SCENES = {"cornell": ROOT / "scenes/cornell/cornell.usda",
          "dome_sphere": OUT / "dome_sphere.usda",
          "glossy_plane": OUT / "glossy_plane.usda",
          "sun_plane": OUT / "sun_plane.usda"}
RESOLUTION = (48, 48)


def reference(path, batches, spp, threads):
    """(mean, standard error of the mean), both (H, W, 3) float32, over `batches` seeds."""
    recorded, _ = mitsuba_scene.record(path)
    scene, _ = mitsuba_scene.mitsuba_scene(recorded, RESOLUTION)
    images = np.stack([mitsuba_scene.render(scene, spp, seed, threads)[0] for seed in range(batches)])
    return images.mean(axis=0), images.std(axis=0, ddof=1) / np.sqrt(batches)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--batches", type=int, default=64)
    parser.add_argument("--spp", type=int, default=256, help="samples per pixel of each batch")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--scenes", default=",".join(SCENES))
    args = parser.parse_args(argv)
    import mitsuba
    from gi import _core
    index_file = OUT / "references.json"
    index = json.loads(index_file.read_text()) if index_file.exists() else {}
    for name in args.scenes.split(","):
        start = time.perf_counter()
        mean, standard_error = reference(SCENES[name], args.batches, args.spp, args.threads)
        meta = {"mitsuba": mitsuba.__version__, "variant": mitsuba_scene.VARIANT, "integrator": "path",
                "scene": str(SCENES[name].relative_to(ROOT)), "batches": args.batches, "spp_per_batch": args.spp,
                "spp": args.batches * args.spp, "resolution": list(RESOLUTION)}
        _core.write_rgb_exr(str(OUT / f"{name}.exr"), np.ascontiguousarray(mean, np.float32),
                            {k: str(v) for k, v in meta.items()})
        _core.write_rgb_exr(str(OUT / f"{name}_se.exr"), np.ascontiguousarray(standard_error, np.float32),
                            {"content": "standard error of the mean in " + f"{name}.exr"})
        index[name] = meta
        print(f"{name}: {meta['spp']} spp in {time.perf_counter() - start:.0f} s, mean {mean.mean():.5g}, "
              f"median relative standard error {np.median(standard_error / np.maximum(mean, 1e-9)):.3g}")
    index_file.write_text(json.dumps(index, indent=2, sort_keys=True) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
