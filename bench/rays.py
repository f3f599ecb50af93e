"""Rays per second: the path tracer against Embree alone, on the same scene and threads.

Both figures come from this one run (machines are shared and noisy, so only the ratio is
meaningful): the path tracer renders the scene, counting every ray it casts (camera,
bounce and shadow rays); then Embree casts the same number of incoherent closest-hit rays
(uniform origins in the scene's bounding sphere, uniform directions) in the same scene.

    .venv/bin/python bench/rays.py [SCENE ...] [--spp 16] [--resolution 256 256]
"""
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def measure(scene_path, spp, resolution, threads):
    import gi
    from gi import _core

    start = time.perf_counter()
    loaded = gi.load_stage(str(scene_path))
    load_seconds = time.perf_counter() - start
    scene = loaded.scene
    scene.commit()
    build_seconds = scene.stats()["build_seconds"]

    settings = _core.RenderSettings()
    settings.width, settings.height = resolution or loaded.resolution
    settings.spp = spp
    settings.integrator = "path"
    settings.threads = threads
    result = _core.render(scene, settings)
    rays = int(result.stats["rays"])
    renderer_rps = result.stats["rays_per_second"]
    embree = _core.embree_ray_benchmark(scene, rays, seed=1, threads=threads)
    return {
        "scene": scene_path.name,
        "load_s": load_seconds,
        "bvh_build_s": build_seconds,
        "rays": rays,
        "renderer_rays_per_s": renderer_rps,
        "samples_per_s": result.stats["samples_per_second"],
        "embree_rays_per_s": embree["rays_per_second"],
        "ratio": renderer_rps / embree["rays_per_second"],
        "peak_memory_mb": _core.peak_memory_bytes() / 2**20,
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", type=Path, default=sorted(ROOT.glob("scenes/*/*.usda")),
                        help="USD scenes (default: every scenes/*/*.usda)")
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--resolution", type=int, nargs=2)
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args(argv)
    print(f"{'scene':<16} {'load s':>7} {'BVH s':>7} {'rays':>11} {'renderer rays/s':>16} "
          f"{'Embree rays/s':>14} {'ratio':>6} {'samples/s':>11} {'peak MB':>8}")
    for path in args.scenes:
        r = measure(path, args.spp, args.resolution, args.threads)
        print(f"{r['scene']:<16} {r['load_s']:>7.3f} {r['bvh_build_s']:>7.3f} {r['rays']:>11,} "
              f"{r['renderer_rays_per_s']:>16,.0f} {r['embree_rays_per_s']:>14,.0f} {r['ratio']:>6.2f} "
              f"{r['samples_per_s']:>11,.0f} {r['peak_memory_mb']:>8.0f}")


if __name__ == "__main__":
    sys.exit(main())
