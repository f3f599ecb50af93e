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
(consistent: its radii shrink) with every other light deactivated. Each takes half the time.
"""
from pathlib import Path

import numpy as np

SUN = "DistantLight"


def _stage_with(path: Path, keep_suns: bool):
    """The stage of `path` with, in its session layer, either its suns or its other lights off."""
    from pxr import Usd, UsdLux
    stage = Usd.Stage.Open(str(path))
    stage.SetEditTarget(stage.GetSessionLayer())
    suns = 0
    for prim in stage.Traverse():
        if not prim.HasAPI(UsdLux.LightAPI) or prim.GetTypeName() == "PortalLight":
            continue
        is_sun = prim.GetTypeName() == SUN
        suns += is_sun
        if is_sun != keep_suns:
            prim.SetActive(False)
    return stage, suns


def reference(path, seconds, render_image, seed=1000):
    """(linear image, description) of the stage at `path`: the path tracer's alone where it has no
    distant light, else the path tracer without its suns plus the progressive photon map of its
    suns alone. render_image(loaded, integrator, seconds, seed) -> (image, spp, wall seconds)."""
    from gi.loader import load_stage
    path = Path(path)
    stage, suns = _stage_with(path, keep_suns=False)
    if suns == 0:
        image, spp, wall = render_image(load_stage(str(path)), "path", seconds, seed)
        return image, f"path {spp} spp in {wall:.0f} s"
    others, others_spp, others_wall = render_image(load_stage(str(path), stage=stage), "path", seconds / 2, seed)
    sun_stage, _ = _stage_with(path, keep_suns=True)
    sun, sun_spp, sun_wall = render_image(load_stage(str(path), stage=sun_stage), "progressivePhotonMap", seconds / 2,
                                          seed)
    return others + sun, (f"path without the sun {others_spp} spp in {others_wall:.0f} s + progressivePhotonMap of "
                          f"the sun alone {sun_spp} spp in {sun_wall:.0f} s")
