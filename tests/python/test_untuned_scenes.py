"""Every technique on a scene nobody tuned it for (issue 15): the glazed-window room of
scenes/window_room, where all light comes in through a 6 mm glass pane. At default parameters
(unbounded depths) each technique's mean must be the path-traced reference's within its measured
bias and noise (MEAN_BOUNDS) and it must have no more local outliers (splotches; gi.metrics.local_outlier_share) than the path
tracer at the same samples per pixel.

The test renders the room under the sky alone: its 0.53-degree sun, seen from the room only
through the glass, is reached by a path tracer only when a BSDF-sampled ray happens to hit it
(about 1 in 10^5 per bounce), so no path-traced reference of the sunlit room converges in a
test's time, nor in hours (see README, "A reference per light")."""
import numpy as np
import pytest

from conftest import ROOT
from gi import _core, metrics
from gi.loader import load_stage

SKY_ROOM = ROOT / "scenes" / "window_room" / "window_room_sky.usda"
SIZE = (64, 48)
REFERENCE_SPP = 2048   # mean's relative noise ~0.2% (two 1024-spp halves differ by < 0.5%)
SPP = 8

# |image mean / reference mean - 1| must stay below |bias| + 4 sd, the bias and sd those of the
# ratio at 8 spp measured over seeds 1-8 against the mean of five 2048-spp references (seeds
# 100-104, 0.08136; one reference's own relative sd 0.0007, added in quadrature), mean (sd):
#   irradianceCache 1.0044 (0.0127), adaptiveIrradianceCache 0.9843 (0.0058): the records' noise
#     at the default 108 paths moves a 64x48 image's mean by about 1%;
#   photonMapIrradianceCache 0.9978 (0.0126), photonMapFinalGather 0.9963 (0.0028) (0.9981
#     (0.0015) since its precomputed irradiance measures the surface in sparse discs);
#   progressivePhotonMap 0.9920 (0.0034) since its lookups measure the surface in their disc
#     (disc_area.h; 0.9901 (0.0035) before): consistent but biased dark at few iterations, its
#     radius falling as N^(-1/6) and its bias as N^(-1/3), so it is held to its measured bias at
#     8 spp, and test_progressive_photon_map_converges below to the bias's rate of fall.
#   (Before photon estimates were corrected for the share of their disc the surface covers
#   (PhotonEstimate::coverageCorrected) and the photon cache's records kept off edges:
#   photonMapIrradianceCache 1.0081 (0.0129), photonMapFinalGather 0.9916 (0.0027),
#   progressivePhotonMap 0.9812 (0.0032).)
# (The bound was 2% for every technique, which seed 1 passed: seed 3 of irradianceCache,
# 4 and 5 of photonMapIrradianceCache, 4 of adaptiveIrradianceCache, 4, 5 and 8 of
# progressivePhotonMap fail it.)
MEAN_BOUNDS = {"irradianceCache": 0.056, "adaptiveIrradianceCache": 0.039, "photonMapIrradianceCache": 0.053,
               "photonMapFinalGather": 0.015, "progressivePhotonMap": 0.022}
TECHNIQUES = sorted(MEAN_BOUNDS)


@pytest.fixture(scope="module")
def sky_room():
    return load_stage(str(SKY_ROOM))


def render(loaded, integrator, spp, seed=1):
    s = _core.RenderSettings()
    s.width, s.height = SIZE
    s.spp, s.integrator, s.seed = spp, integrator, seed
    result = _core.render(loaded.scene, s)
    assert result.stats["non_finite_samples"] == 0
    # Unbounded depths end by Russian roulette; the 1024 cap stops only paths trapped in the glass
    # pane (total internal reflection). Measured at 8 spp over seeds 1-8: 0 capped paths, except
    # photonMapIrradianceCache 2 (seed 4) and photonMapFinalGather 1 (seeds 2, 3); the 2048-spp
    # path-traced references (seeds 100-104) 0. At the highest rate seen, 2 in 8 renders, a Poisson
    # count reaches 4 with probability 1.4e-4: at most 3.
    assert result.stats["depth_capped_paths"] <= 3, result.stats["depth_capped_paths"]
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
    assert abs(ratio - 1) < MEAN_BOUNDS[integrator]
    assert outliers <= path_outliers


# The progressive photon map's error e^2 (mean squared error less the reference's own variance, over
# the reference's mean^2) falls with the iterations N as N^(-2/3) at alpha = 2/3 (Hachisuka & Jensen;
# Knaus & Zwicker: the radius^2, and so the bias, falls as N^(alpha - 1) = N^(-1/3), the variance as
# N^(-alpha)): 4^(2/3) = 2.52x from 4 to 16 spp and again to 64. Measured over seeds 1-4, each against
# its own 2048-spp reference made of two halves (seeds 500 + ...): the reference's variance, relative,
# 0.00192 (sd 0.00016); e^2 0.0185 (sd 0.0014), 0.0033 (0.00056), 0.00126 (0.00017);
# e^2(next) - e^2(this) / 2.52: -0.0040 (0.00022; the first iterations' eye-pass noise falls as 1/N
# too) and -0.00005 (0.00015): bounds 4 sd. (The raw RMSE's last step is small: the reference's
# noise is most of it.)
REFERENCE_VARIANCE = 0.00192
PPM_RATE = 4 ** (2 / 3)
PPM_BOUNDS = (0.0009, 0.0006)


def test_progressive_photon_map_converges(sky_room, reference):
    """Consistency: the progressive photon map's error against the path-traced reference falls as
    samples (iterations, each a new photon map with a smaller radius) are added, at the rate its
    shrinking radius gives (PPM_RATE). At these sample counts a radius that never shrank would still
    pass (its bias is below the noise: e^2 0.0190, 0.0036, 0.0017 with the radius fixed); the
    schedule itself is checked in tests/cpp/test_photon_map.cpp (RadiusShrinksAsHachisukaAndJensen)."""
    errors = [float(np.mean((render(sky_room, "progressivePhotonMap", spp) - reference) ** 2)) / float(reference.mean()) ** 2
              - REFERENCE_VARIANCE for spp in (4, 16, 64)]
    print("progressivePhotonMap e^2 at 4, 16, 64 spp:", [f"{e:.5f}" for e in errors])
    for bound, this, following in zip(PPM_BOUNDS, errors, errors[1:]):
        assert following - this / PPM_RATE < bound, errors
