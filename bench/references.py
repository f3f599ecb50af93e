"""References for the benches where a sun is seen only through glass.

There the path tracer finds the sun only when a BSDF-sampled ray, refracted by the glass, reaches
its 0.53 degree disc: its estimate is heavy-tailed, and a render of minutes reads far less than the
mean it converges to. Measured (README, "A reference per light"): Sibenik under the sun alone, the
progressive photon map read 1.96 times the path tracer (60 s each, 160x120, the path tracer's two
seeds 1.2% apart); under a 4 x 4 m pane, 32x32 pixels, the photon maps read 0.1887 and the path
tracer 0.175 at 4,096 samples per pixel and 0.180-0.194 at 40,000 (three seeds). The sky, which
BSDF-sampled rays find easily, the path tracer renders well, and a photon map of the sky carries
its own bias.

Light transport is linear in the lights, so the reference is the sum of two renders of the same
stage: the path tracer with every distant light (sun) deactivated, and the progressive photon map
(consistent: its radii shrink) with every other light deactivated. Each takes half the time. The
split is gi.reference's (`gi reference --sun-by-photons`); here each half is one timed render.
"""
from pathlib import Path


def reference(path, glass, glass_reference, seconds, render_image, seed=1000):
    """(linear image, description) of the stage at `path`: the path tracer's, unless its sun is
    seen only through glass (`glass`): then, with `glass_reference` "per-light" and a distant
    light, the path tracer without its suns plus the progressive photon map of its suns alone, or
    else `glass_reference`'s integrator alone.
    render_image(loaded, integrator, seconds, seed) -> (image, spp, wall seconds)."""
    from gi.loader import load_stage
    from gi.reference import SUN_INTEGRATOR, stage_with_suns
    path = Path(path)
    stage, suns = stage_with_suns(path, keep=False) if glass and glass_reference == "per-light" else (None, 0)
    if not suns:
        integrator = glass_reference if glass and glass_reference != "per-light" else "path"
        image, spp, wall = render_image(load_stage(str(path)), integrator, seconds, seed)
        return image, f"{integrator} {spp} spp in {wall:.0f} s"
    others, others_spp, others_wall = render_image(load_stage(str(path), stage=stage), "path", seconds / 2, seed)
    sun_stage, _ = stage_with_suns(path, keep=True)
    sun, sun_spp, sun_wall = render_image(load_stage(str(path), stage=sun_stage), SUN_INTEGRATOR, seconds / 2, seed)
    return others + sun, (f"path without the sun {others_spp} spp in {others_wall:.0f} s + {SUN_INTEGRATOR} of "
                          f"the sun alone {sun_spp} spp in {sun_wall:.0f} s")
