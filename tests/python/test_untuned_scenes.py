"""Every technique on a scene nobody tuned it for (issue 15): the glazed-window room of
scenes/window_room, where all light comes in through a 6 mm glass pane. At default parameters
(unbounded depths) each technique's mean must be within 2% of a path-traced reference and it
must have no more local outliers (splotches; gi.metrics.local_outlier_share) than the path
tracer at the same samples per pixel.

The test renders the room under the sky alone: its 0.53-degree sun, seen from the room only
through the glass, is reached by a path tracer only when a BSDF-sampled ray happens to hit it
(about 1 in 10^5 per bounce), so no path-traced reference of the sunlit room converges in a
test's time, nor in hours (see README, untuned scenes)."""
import numpy as np
import pytest

from conftest import ROOT
from gi import _core, metrics
from gi.loader import load_stage

SKY_ROOM = ROOT / "scenes" / "window_room" / "window_room_sky.usda"
SIZE = (64, 48)
REFERENCE_SPP = 2048   # mean's relative noise ~0.2% (two 1024-spp halves differ by < 0.5%)
SPP = 8
TECHNIQUES = ["irradianceCache", "adaptiveIrradianceCache", "photonMapIrradianceCache", "photonMapFinalGather",
              "progressivePhotonMap"]


@pytest.fixture(scope="module")
def sky_room():
    return load_stage(str(SKY_ROOM))


def render(loaded, integrator, spp, seed=1):
    s = _core.RenderSettings()
    s.width, s.height = SIZE
    s.spp, s.integrator, s.seed = spp, integrator, seed
    result = _core.render(loaded.scene, s)
    assert result.stats["non_finite_samples"] == 0
    assert result.stats["depth_capped_paths"] == 0
    return np.asarray(result.color)


@pytest.fixture(scope="module")
def reference(sky_room):
    return render(sky_room, "path", REFERENCE_SPP, seed=100)


@pytest.fixture(scope="module")
def path_noise(sky_room):
    a, b = render(sky_room, "path", SPP, seed=1), render(sky_room, "path", SPP, seed=2)
    return a, metrics.block_noise(a, b)


@pytest.mark.parametrize("integrator", TECHNIQUES)
def test_every_technique_matches_the_path_traced_reference(sky_room, reference, path_noise, integrator):
    image = render(sky_room, integrator, SPP)
    ratio = image.mean() / reference.mean()
    path_image, sigma = path_noise
    outliers = metrics.local_outlier_share(image, reference, sigma)
    path_outliers = metrics.local_outlier_share(path_image, reference, sigma)
    print(f"{integrator}: mean / reference {ratio:.4f}, outlier blocks {outliers:.3f} (path {path_outliers:.3f})")
    assert abs(ratio - 1) < 0.02
    assert outliers <= path_outliers


def test_progressive_photon_map_converges(sky_room, reference):
    """Consistency: the progressive photon map's error against the path-traced reference falls as
    samples (iterations, each a new photon map with a smaller radius) are added (a fixed photon
    map levels off at its bias). Measured RMSE at 4, 16 and 64 spp: 0.0117, 0.0059, 0.0044; the
    last step is smaller because the 2048-spp reference's own noise is part of what is measured,
    so the test asks for a halving over the first step and a fall over the second."""
    errors = [float(np.sqrt(np.mean((render(sky_room, "progressivePhotonMap", spp) - reference) ** 2)))
              for spp in (4, 16, 64)]
    print("progressivePhotonMap RMSE at 4, 16, 64 spp:", [f"{e:.5f}" for e in errors])
    assert errors[1] < 0.6 * errors[0] and errors[2] < errors[1]
