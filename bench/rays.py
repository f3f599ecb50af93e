"""Rays per second: the path tracer against Embree alone, on the same scene and threads.

Both figures come from this one run (machines are shared and noisy, so only the ratio is
meaningful): the path tracer renders the scene, counting every ray it casts (camera,
bounce and shadow rays); then Embree casts the same number of incoherent closest-hit rays
(uniform origins in the scene's bounding box, uniform directions, generated before its clock
starts, so its figure is Embree's traversal alone) in the same scene. The two
alternate for --rounds rounds, so a burst of load on a shared machine hits one round, not one
side: the median ratio is reported with the lowest and highest, and the median ratio of
process CPU time per ray (Embree's over the renderer's), which other processes on a shared
machine disturb less than wall time. Last, "Embree share": the render's own rays, recorded and cast
through Embree alone, over the render's time; it bounds the ratio above a renderer could reach
with free shading, for this scene's rays. Beside it, how much faster Embree casts those same rays
(CPU time) in wavefront order (waves of 1,024 paths, each step's rays together), one by one
("wavefront") and as 8-wide packets ("packets8"): what tracing whole waves could gain in Embree.

    .venv/bin/python bench/rays.py [SCENE ...] [--spp 16] [--resolution 256 256] [--rounds 5]
"""
import statistics
import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
REPLAY_ORDERS = ("render", "wavefront", "wavefront-packets8")


def measure(scene_path, spp, resolution, threads, rounds):
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
    renderer_rps, embree_rps, samples_ps, cpu_ratios = [], [], [], []
    for _ in range(rounds):
        cpu = time.process_time()
        result = _core.render(scene, settings)
        renderer_cpu = time.process_time() - cpu
        rays = int(result.stats["rays"])
        renderer_rps.append(result.stats["rays_per_second"])
        samples_ps.append(result.stats["samples_per_second"])
        embree = _core.embree_ray_benchmark(scene, rays, seed=1, threads=threads)
        embree_rps.append(embree["rays_per_second"])
        embree_cpu = embree["cpu_seconds"]  # the casting only: its rays are generated before
        cpu_ratios.append(embree_cpu / renderer_cpu)  # same ray count: the ratio of CPU-seconds per ray
    peak_mb = _core.peak_memory_bytes() / 2**20  # before the replay's recorded rays
    # Embree's share of the render: the render's own rays, recorded and cast through Embree alone
    # (a quarter of the samples keeps the recording's memory modest), in rounds as above.
    # The same rays in wavefront order (waves of paths, each step's rays together), cast one by one
    # and as Embree's 8-wide packets: what a wavefront renderer could gain in Embree.
    settings.spp = max(1, spp // 4)
    shares, cpu_shares = [], []
    replay_cpu = {order: [] for order in REPLAY_ORDERS}
    for _ in range(rounds):
        for order in REPLAY_ORDERS:
            replay = _core.embree_replay_render_rays(scene, settings, order)
            replay_cpu[order].append(replay["replay_cpu_seconds"])
            if order == "render":
                shares.append(replay["replay_seconds"] / replay["render_seconds"])
                cpu_shares.append(replay["replay_cpu_seconds"] / replay["render_cpu_seconds"])
    render_order = statistics.median(replay_cpu["render"])
    ratios = [r / e for r, e in zip(renderer_rps, embree_rps)]
    median = statistics.median_low(ratios)
    i = ratios.index(median)
    return {
        "scene": scene_path.name,
        "load_s": load_seconds,
        "bvh_build_s": build_seconds,
        "rays": rays,
        "renderer_rays_per_s": renderer_rps[i],
        "samples_per_s": samples_ps[i],
        "embree_rays_per_s": embree_rps[i],
        "ratio": median,
        "ratio_low": min(ratios),
        "ratio_high": max(ratios),
        "cpu_ratio": statistics.median(cpu_ratios),
        "peak_memory_mb": peak_mb,
        "embree_share": statistics.median(shares),
        "embree_share_cpu": statistics.median(cpu_shares),
        # Embree's CPU time on the render's rays in render order over that in each order
        "replay_speedup": {order: render_order / statistics.median(replay_cpu[order]) for order in REPLAY_ORDERS},
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", type=Path, default=sorted(ROOT.glob("scenes/*/*.usda")),
                        help="USD scenes (default: every scenes/*/*.usda)")
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--resolution", type=int, nargs=2)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--rounds", type=int, default=5, help="alternating renderer/Embree rounds (median reported)")
    args = parser.parse_args(argv)
    print(f"{'scene':<16} {'load s':>7} {'BVH s':>7} {'rays':>11} {'renderer rays/s':>16} "
          f"{'Embree rays/s':>14} {'ratio':>6} {'low-high':>10} {'CPU ratio':>9} {'samples/s':>11} {'peak MB':>8} "
          f"{'Embree share':>12} {'wavefront':>9} {'packets8':>8}")
    for path in args.scenes:
        r = measure(path, args.spp, args.resolution, args.threads, max(1, args.rounds))
        print(f"{r['scene']:<16} {r['load_s']:>7.3f} {r['bvh_build_s']:>7.3f} {r['rays']:>11,} "
              f"{r['renderer_rays_per_s']:>16,.0f} {r['embree_rays_per_s']:>14,.0f} {r['ratio']:>6.2f} "
              f"{r['ratio_low']:>4.2f}-{r['ratio_high']:<4.2f} {r['cpu_ratio']:>9.2f} "
              f"{r['samples_per_s']:>11,.0f} {r['peak_memory_mb']:>8.0f} "
              f"{r['embree_share']:>5.2f} ({r['embree_share_cpu']:.2f} CPU) "
              f"{r['replay_speedup']['wavefront']:>9.2f} {r['replay_speedup']['wavefront-packets8']:>8.2f}")


if __name__ == "__main__":
    sys.exit(main())
