"""Every technique on the untuned scenes of issue 15, at equal time, against a converged reference.

Scenes: the glazed-window room with its sun and sky (all light through a 6 mm pane), the same room
under the sky alone, Sponza under sun and sky, Sibenik under sun and sky through its window glass,
and the same with portal lights over its windows (sibenik-portals).
For each: a reference (the path tracer, unbounded depth, for --reference-seconds; or, where a sun is
seen only through glass and no path tracer converges, the path tracer without the sun plus the
progressive photon map of the sun alone, bench/references.py, or --glass-reference's integrator), then every
technique at its defaults with a --seconds time limit. Printed per scene and technique: the seconds
actually spent, mean / reference, RMSE on sRGB8, mean FLIP, the local-outlier share (8x8 blocks
beyond 4 sigma of the path tracer's block noise at the same time; gi.metrics.local_outlier_share)
and the records or photons. Figures are from one run on a shared machine: compare within a table.

    .venv/bin/python bench/untuned.py [--scenes room,room-sky,sponza,sibenik,sibenik-portals] [--resolution 128 96]
        [--seconds 5] [--reference-seconds 120] [--integrators path,irradianceCache,...]
    (an integrator may carry parameters: photonMapFinalGather:gatherBounces=0; separate those with ';';
    a scene may also be a USD file's path, rendered against the path tracer)

The McGuire Cornell boxes (box-water, box-sphere, box-mirror) are ../shared/assets/cornell's OBJ
variants, imported by `gi import` into a temporary folder as a user would, with the camera
`gi render` frames the scene with: a glossy near-mirror ball (roughness 0.21), a rough glass ball
(opacity 0.9), rough water, and a two-sided emitting panel 1 cm under the ceiling. Nobody tuned
gi on them; their references are the path tracer's.
"""
import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

import references

ROOT = Path(__file__).resolve().parent.parent

SCENES = {"cornell": (ROOT / "scenes/cornell/cornell.usda", False),
          "room": (ROOT / "scenes/window_room/window_room.usda", True),
          "room-sky": (ROOT / "scenes/window_room/window_room_sky.usda", False),
          "sponza": (ROOT / "scenes/sponza/sponza.usda", False),
          "sibenik": (ROOT / "scenes/sibenik/sibenik_sky.usda", True),
          "sibenik-portals": (ROOT / "scenes/sibenik/sibenik_sky_portals.usda", True)}
IMPORTED = {"box-water": "CornellBox-Water.obj", "box-sphere": "CornellBox-Sphere.obj",
            "box-mirror": "CornellBox-Mirror.obj"}
TECHNIQUES = ["path", "irradianceCache", "adaptiveIrradianceCache", "photonMapIrradianceCache",
              "photonMapFinalGather", "progressivePhotonMap"]
COUNTS = ["records", "globalMapPhotons", "causticMapPhotons", "photonsStored"]


def render(loaded, integrator, resolution, spp, seconds, seed=1):
    """integrator: a name, or name:param=value,... (e.g. photonMapFinalGather:gatherBounces=0)."""
    from gi import _core
    name, _, given = integrator.partition(":")
    s = _core.RenderSettings()
    s.width, s.height = resolution
    s.integrator, s.spp, s.seed, s.time_limit = name, spp, seed, seconds
    s.params = {key: float(value) for key, value in (pair.split("=") for pair in given.split(",") if pair)}
    start = time.perf_counter()
    result = _core.render(loaded.scene, s)
    return np.asarray(result.color), result.stats, time.perf_counter() - start


def scene_path(name, folder):
    """(USD path, whether the sun is seen through glass) of a scene name or a USD file's path."""
    if name in SCENES:
        return SCENES[name]
    if name in IMPORTED:
        from gi.importer import import_file
        output = Path(folder) / f"{name}.usda"
        import_file(f"cornell/{IMPORTED[name]}", output, absolute_paths=True)
        return output, False
    return Path(name), False


def main():
    from gi import metrics
    from gi.loader import load_stage
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", default="room,room-sky,sponza,sibenik")
    parser.add_argument("--resolution", type=int, nargs=2, default=(128, 96))
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--reference-seconds", type=float, default=120.0)
    parser.add_argument("--glass-reference", default="per-light",
                        help="per-light (bench/references.py) or an integrator's name")
    parser.add_argument("--integrators", default=",".join(TECHNIQUES))
    args = parser.parse_args()
    resolution = tuple(args.resolution)
    folder = tempfile.TemporaryDirectory(prefix="gi-untuned-")
    for name in args.scenes.split(","):
        path, glass = scene_path(name, folder.name)
        loaded = load_stage(str(path))
        def render_image(stage_loaded, integrator, seconds, seed):
            image, stats, wall = render(stage_loaded, integrator, resolution, 1 << 24, seconds, seed=seed)
            return image, int(stats["spp"]), wall
        reference, described = references.reference(path, glass, args.glass_reference, args.reference_seconds,
                                                    render_image)
        path_a, _, _ = render(loaded, "path", resolution, 1 << 24, args.seconds, seed=11)
        path_b, _, _ = render(loaded, "path", resolution, 1 << 24, args.seconds, seed=12)
        sigma = metrics.block_noise(path_a, path_b)
        print(f"\n## {name} ({path.name}), {resolution[0]}x{resolution[1]}: reference {described}, "
              f"mean {reference.mean():.5f}")
        print("| technique | seconds | spp | mean / ref | RMSE sRGB8 | FLIP | outlier blocks | records / photons |")
        print("|---|---|---|---|---|---|---|---|")
        for integrator in (args.integrators.split(";") if ";" in args.integrators else args.integrators.split(",")):
            image, stats, wall = render(loaded, integrator, resolution, 1 << 24, args.seconds)
            m = metrics.compare(image, reference)
            counts = ", ".join(f"{k} {int(stats[k])}" for k in COUNTS if k in stats)
            print(f"| {integrator} | {wall:.1f} | {int(stats['spp'])} | {image.mean() / reference.mean():.3f} | "
                  f"{m.rmse_srgb8:.2f} | {m.flip:.4f} | {metrics.local_outlier_share(image, reference, sigma):.3f} | "
                  f"{counts} |", flush=True)


if __name__ == "__main__":
    main()
