"""Irradiance caching (issue 4) and photon mapping (issue 5) against a path-traced reference on the
project's Cornell box, scenes/cornell/cornell.usda (../shared/specs/cornell.md).

The error measure is the error of the *indirect* component. Every integrator under test is the ray
tracer (emission, direct light by light sampling, specular recursion) plus an indirect term, and
with the same seed, samples and light samples the ray tracer's own part draws the same random
numbers in `direct` as in the caches (they draw nothing from the pixel's sampler), so
render(integrator) - render("direct") is that integrator's indirect light without the direct
light's noise or the visible light's edges. The reference's indirect light is the path tracer's
image minus a many-sample `direct` image. The reference (two independent 2048-spp halves at 40x40)
is rendered once per module and carries about 0.003 of noise per pixel; every error below is
measured against the same reference, so that noise adds the same amount to each setting's error,
and its halves' difference tells how much (`excess_error`).

Run with -s to see the figures."""
import math
import tempfile
from pathlib import Path

import numpy as np
import pytest

from conftest import CORNELL, render

RESOLUTION = (40, 40)
REFERENCE_SPP = 4096  # two halves; its noise is most of e^2 below, and of the indirect mean's spread
SPP = 16
LIGHT_SAMPLES = 4  # in the caches and in the `direct` images subtracted from them

# Geometry from the specification (sections 2 and 5).
EYE = np.array([0.0, 0.0, 3.9])
TAN_HALF_FOV = 0.357143
SPHERE_CENTER, SPHERE_RADIUS = np.array([0.0, -0.6, 0.0]), 0.4
CONTACT = np.array([0.0, -1.0, 0.0])  # where the sphere rests on the floor
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def luminance(rgb):
    return rgb @ LUMINANCE


def rgb(image):
    return np.asarray(image, dtype=np.float64)[..., :3]


def view_rays(width, height, eye=EYE, tan_x=TAN_HALF_FOV, tan_y=TAN_HALF_FOV, pitch_degrees=0.0):
    """Unit directions of the pixel-centre rays of a pinhole camera looking down -z, tilted by
    `pitch_degrees` about x (negative looks down), as USD's xformOp:rotateX."""
    j, i = np.mgrid[0:height, 0:width]
    d = np.stack([(2 * (i + 0.5) / width - 1) * tan_x, (1 - 2 * (j + 0.5) / height) * tan_y,
                  -np.ones((height, width))], axis=-1)
    a = math.radians(pitch_degrees)
    c, s = math.cos(a), math.sin(a)
    d = np.stack([d[..., 0], c * d[..., 1] - s * d[..., 2], s * d[..., 1] + c * d[..., 2]], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def first_hits(directions, eye):
    """(hits the glass sphere, floor point where the ray reaches the floor first, else NaN)."""
    oc = eye - SPHERE_CENTER
    b = (directions * oc).sum(-1)
    disc = b * b - (oc @ oc - SPHERE_RADIUS ** 2)
    sphere = (disc > 0) & (-b - np.sqrt(np.maximum(disc, 0)) > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(directions[..., 1] < 0, (-1 - eye[1]) / directions[..., 1], np.nan)
    floor = eye + t[..., None] * directions
    inside = (np.abs(floor[..., 0]) <= 1) & (np.abs(floor[..., 2]) <= 1) & ~sphere
    floor[~inside] = np.nan
    return sphere, floor


def dilate(mask):
    out = mask.copy()
    out[1:, :] |= mask[:-1, :]
    out[:-1, :] |= mask[1:, :]
    out[:, 1:] |= mask[:, :-1]
    out[:, :-1] |= mask[:, 1:]
    return out


def floor_under_sphere(floor):
    """Floor points within the sphere's radius of where it touches the floor (the caustic and
    the sphere's shadow)."""
    distance = np.hypot(floor[..., 0] - CONTACT[0], floor[..., 2] - CONTACT[2])
    return np.nan_to_num(distance, nan=np.inf) < SPHERE_RADIUS


class Reference(tuple):
    """(indirect light, pixels away from the glass sphere), and the per-pixel variance of the
    indirect light (mean over channels) from the halves it was made of."""
    variance = None


@pytest.fixture(scope="module")
def reference():
    """The path-traced reference's indirect light, and the pixels away from the glass sphere
    (the sphere, the floor under it and a pixel around both)."""
    paths = [rgb(render(CORNELL, "path", spp=REFERENCE_SPP // 2, seed=seed, resolution=RESOLUTION)[0]) for seed in (1, 2)]
    directs = [rgb(render(CORNELL, "direct", spp=512, seed=seed, resolution=RESOLUTION, lightSamples=LIGHT_SAMPLES)[0])
               for seed in (1, 2)]
    sphere, floor = first_hits(view_rays(*RESOLUTION), EYE)
    away_from_glass = ~dilate(sphere | floor_under_sphere(floor))
    result = Reference(((paths[0] + paths[1]) / 2 - (directs[0] + directs[1]) / 2, away_from_glass))
    result.variance = (((paths[0] - paths[1]) ** 2 + (directs[0] - directs[1]) ** 2).sum(-1) / 3 / 4)
    return result


def excess_error(image, reference):
    """The mean squared error less the reference's own variance, over the square of the reference's
    mean luminance: an estimate of the image's bias^2 + variance, relative."""
    reference_indirect = reference[0]
    squared = ((image - reference_indirect) ** 2).sum(-1) / 3 - reference.variance
    return float(squared.mean() / luminance(reference_indirect).mean() ** 2)


def indirect(integrator, seed, **params):
    """An integrator's indirect light (its image minus the ray tracer's with the same samples)."""
    image, result, _ = render(CORNELL, integrator, spp=SPP, seed=seed, resolution=RESOLUTION,
                              lightSamples=LIGHT_SAMPLES, **params)
    direct, _, _ = render(CORNELL, "direct", spp=SPP, seed=seed, resolution=RESOLUTION, lightSamples=LIGHT_SAMPLES)
    return rgb(image) - rgb(direct), result.stats


def rmse(image, reference, mask=None):
    squared = ((image - reference) ** 2).sum(-1) / 3
    return float(np.sqrt(squared[mask].mean() if mask is not None else squared.mean()))


def laplacian_energy(image, reference):
    """Energy of the discrete Laplacian of the luminance error (tests/cpp/test_irradiance_cache.cpp's
    measure): seams and blotches, not a smooth bias."""
    e = luminance(image - reference)
    lap = 4 * e[1:-1, 1:-1] - e[:-2, 1:-1] - e[2:, 1:-1] - e[1:-1, :-2] - e[1:-1, 2:]
    return float((lap ** 2).mean())


# --- issue 4: irradiance caching ------------------------------------------------------------------

def test_irradiance_cache_error_falls_as_accuracy_tightens(reference):
    """The cache's error on the diffuse surfaces falls as the accuracy tightens from 0.125 to 0.5.

    Measured on the pixels away from the glass sphere: the caustic under it is a sharp feature
    that hemisphere-sampled records do not resolve at any accuracy (their caustic paths are noisy
    and the records at least 1.5 pixels apart), so with it the whole image's indirect error stays
    at about 0.008 from accuracy 0.5 on; caustics are the photon map's part (issue 5, below). maxSpacing is the
    image's width so that the accuracy alone sets the record radii (the default 10-pixel cap
    makes every accuracy up to 0.25 the same cache at 40x40), and 512 paths per record keep the
    records' noise below the interpolation error. Beyond accuracy 0.5 the cache's remaining
    error on this box (measured against an 8192-spp reference: about 0.0035, mostly record and
    reference noise) no longer changes measurably at this resolution.

    The noise: over seeds 0-7 the mean squared error away from the glass falls by 3.8e-5 from
    accuracy 0.125 to 0.5, sd 1.6e-5 per seed (the records' caustic paths make it heavy-tailed);
    over four seeds that is 4.6 sd above zero, so the test asks for a fall there. The steps in
    between fall by 0.8e-5 (sd 1.1e-5) and 2.9e-5 (sd 2.4e-5) per seed: four seeds cannot resolve
    them, and they are not asserted. The cache's energy is bounded in tests/cpp/test_irradiance_cache.cpp
    (CornellBox), on a box without glass: here the records' samples that find the light through the
    glass are clamped as outliers (record_outliers.h), and the cache's indirect light away from the
    glass is 0.95 of the reference's at 2048 paths (sd 1.7% over seeds 0-7; 0.99 with the clamp
    off), 0.97 at 512 paths (sd 5.6%)."""
    reference_indirect, away = reference
    squared_errors, records = [], []
    for accuracy in (0.125, 0.25, 0.5):
        squared, energy = [], []
        for seed in (0, 1, 2, 3):
            image, stats = indirect("irradianceCache", seed, accuracy=accuracy, paths=512, maxSpacing=RESOLUTION[0])
            squared.append(rmse(image, reference_indirect, away) ** 2)
            energy.append(luminance(image)[away].mean() / luminance(reference_indirect)[away].mean())
        squared_errors.append(np.mean(squared))
        records.append(int(stats["records"]))
        print(f"irradianceCache accuracy {accuracy}: {records[-1]} records, indirect RMSE away from the glass "
              f"{math.sqrt(squared_errors[-1]):.5f}, energy {np.round(energy, 3)} of the reference's")
    assert records[0] < records[1] < records[2], records
    assert squared_errors[0] > squared_errors[2], squared_errors


SEAMS_EXCESS_BOUND = 0.0017  # the three-seed sum of adaptive - plain: its mean + 4 sd (docstring below)


def test_adaptive_refinement_has_no_more_discontinuities(reference):
    """At about equal record count (the plain cache at the first accuracy that reaches the adaptive
    cache's records at accuracy 1) the adaptive cache's error has no more high-frequency energy
    than the plain cache's beyond the noise, summed over three seeds. Over the whole image: the
    seams that matter are at the caustic.

    Measured over seeds 0-9 against the module's reference: adaptive - plain per seed -0.00048
    (sd 0.00045; from -0.0011 to +0.00012), so a three-seed sum is -0.0014 (sd 0.00078): 1.8 sd
    below zero, which "adaptive <= plain" needed (seeds 0-2 read -0.0028, lucky). Bound the
    measured mean + 4 sd, 0.0017. The refinement shrinking the wrong records reads +0.0030 and
    fails it; but the adaptive cache's lead comes from its first fill's placement: with the
    refinement switched off, seeds 0-3 read -0.00003, -0.00097, -0.00077, -0.00005 and pass, so
    this does not assert the refinement's own gain."""
    reference_indirect, away = reference
    adaptive_total = plain_total = 0.0
    for seed in (0, 1, 2):
        adaptive, adaptive_stats = indirect("adaptiveIrradianceCache", seed, accuracy=1, paths=512)
        target = adaptive_stats["records"]
        for accuracy in (1, 1.5, 2, 3, 4):
            plain, plain_stats = indirect("irradianceCache", seed, accuracy=accuracy, paths=512)
            if plain_stats["records"] >= target:
                break
        else:
            pytest.fail(f"seed {seed}: no plain cache reached {target:.0f} records")
        a, p = laplacian_energy(adaptive, reference_indirect), laplacian_energy(plain, reference_indirect)
        print(f"seed {seed}: adaptive {target:.0f} records, Laplacian energy {a:.3g}; plain (accuracy {accuracy}) "
              f"{plain_stats['records']:.0f} records, {p:.3g}; RMSE {rmse(adaptive, reference_indirect):.5f} vs "
              f"{rmse(plain, reference_indirect):.5f}")
        adaptive_total += a
        plain_total += p
    print(f"sum over seeds: adaptive {adaptive_total:.3g}, plain {plain_total:.3g}")
    assert adaptive_total - plain_total < SEAMS_EXCESS_BOUND, (adaptive_total, plain_total)


# --- issue 5: photon mapping ----------------------------------------------------------------------

PHOTON_LEVELS = {
    "photonMapFinalGather": [dict(photons=5000, causticPhotons=5000, finalGatherSamples=4),
                             dict(photons=50000, causticPhotons=50000, finalGatherSamples=16),
                             dict(photons=200000, causticPhotons=200000, finalGatherSamples=32)],
    "photonMapIrradianceCache": [dict(photons=5000, causticPhotons=5000, paths=30),
                                 dict(photons=50000, causticPhotons=50000, paths=120),
                                 dict(photons=200000, causticPhotons=200000, paths=480)],
}


# Between consecutive levels: (the factor the error e^2 must fall by at least, 4 sd of
# e^2(next) - e^2(this) / factor), and the bound on the top level's indirect mean. Measured with
# excess_error over seeds 0-5, each against its own reference (two 2048-spp halves), mean (sd):
#   final gathering: e^2 0.115 (0.014), 0.028 (0.0057), 0.014 (0.0064). Its gather rays per sample
#     grow 4x then 2x, and the density estimates' bias (the gather disc's area, k / N) shrinks 10x
#     then 4x, so e^2 must fall at least 4x then 2x: e^2(next) - e^2(this) / factor measured
#     -0.0009 (0.0063) and -0.0001 (0.0042), bounds 4 sd. An error that stops falling at the first
#     step (0.115 -> 0.115: 0.086) fails it; at the second its resolution ends (0.014 -> 0.014:
#     0.007).
#   the photon cache: e^2 0.58 (0.86: a 30-path record now and then catches a caustic path), 0.062
#     (0.0087), 0.035 (0.0074). Its record paths grow 4x at each level, but at its fixed cache
#     accuracy the records' interpolation error stays: the second step falls 1.8x, not 4x. So it is
#     asked only to fall (factor 1, bound 0): the smallest of six first falls is 0.086, the second,
#     0.027 (0.0062), is 4.4 sd above 0.
#   The top level's indirect light away from the glass over the reference's: final gathering 0.9994
#     (0.0030), the photon cache 0.9906 (0.0087), the reference's own noise included (its indirect
#     mean: sd 0.4%): bounds 4 sd, 1.2% and 3.5%.
PHOTON_RATES = {"photonMapFinalGather": [(4, 0.025), (2, 0.017)], "photonMapIrradianceCache": [(1, 0.0), (1, 0.0)]}
PHOTON_MEAN_BOUNDS = {"photonMapFinalGather": 0.012, "photonMapIrradianceCache": 0.035}


@pytest.mark.parametrize("integrator", sorted(PHOTON_LEVELS))
def test_photon_mapping_converges_with_photons_and_gather_rays(reference, integrator):
    """The indirect error over the whole image (caustic included) falls as the photons and the
    gather rays (final-gather rays; the hemisphere paths of the records that photons do not
    cover) grow, at the rate their estimators give (PHOTON_RATES), and carries the reference's
    energy: a constant bias fails the latter."""
    reference_indirect, away = reference
    errors = []
    for params in PHOTON_LEVELS[integrator]:
        image, _ = indirect(integrator, 0, **params)
        errors.append(excess_error(image, reference))
        print(f"{integrator} {params}: indirect e^2 {errors[-1]:.5f} (RMSE {rmse(image, reference_indirect):.5f})")
    for (factor, bound), this, following in zip(PHOTON_RATES[integrator], errors, errors[1:]):
        assert following - this / factor < bound, (errors, factor)
    ratio = luminance(image)[away].mean() / luminance(reference_indirect)[away].mean()
    print(f"{integrator}: indirect light away from the glass {ratio:.4f} of the reference's")
    assert abs(ratio - 1) < PHOTON_MEAN_BOUNDS[integrator], ratio


# The caustic: seen from the scene camera it is a sliver under the sphere, so a second camera looks
# at it from just above the floor in front of the sphere (in a layer over the scene file).
CAUSTIC_EYE = (0.0, -0.9, 1.0)
CAUSTIC_PITCH = -6.5
CAUSTIC_RESOLUTION = (48, 12)
CAUSTIC_TAN_X = math.tan(math.radians(15))
CAUSTIC_FOCAL = 50.0


@pytest.fixture(scope="module")
def caustic_scene():
    w, h = CAUSTIC_RESOLUTION
    horizontal = 2 * CAUSTIC_FOCAL * CAUSTIC_TAN_X
    layer = f"""#usda 1.0
(
    subLayers = [@{CORNELL.as_posix()}@]
)
over "World"
{{
    def Camera "CausticCamera"
    {{
        token projection = "perspective"
        float focalLength = {CAUSTIC_FOCAL}
        float horizontalAperture = {horizontal}
        float verticalAperture = {horizontal * h / w}
        float fStop = 0
        float2 clippingRange = (0.01, 100)
        double3 xformOp:translate = {CAUSTIC_EYE}
        float xformOp:rotateX = {CAUSTIC_PITCH}
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
    }}
}}
"""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "cornell_caustic.usda"
        path.write_text(layer)
        yield path


def render_caustic_view(scene, integrator, spp, seed, **params):
    from gi.render import render_scene
    result, _, _ = render_scene(str(scene), integrator, params, spp, seed, resolution=CAUSTIC_RESOLUTION,
                                camera="/World/CausticCamera")
    return rgb(result.color)


CAUSTIC_RADIUS = 0.2  # the caustic proper: the reference's radiance falls from 0.85 to 0.03 between r = 0.15 and 0.25


def caustic_region(radius):
    """Pixels of the caustic camera that see the floor within `radius` of where the sphere touches it,
    directly, a pixel away from the sphere's silhouette and the image border."""
    w, h = CAUSTIC_RESOLUTION
    rays = view_rays(w, h, np.array(CAUSTIC_EYE), CAUSTIC_TAN_X, CAUSTIC_TAN_X * h / w, CAUSTIC_PITCH)
    sphere, floor = first_hits(rays, np.array(CAUSTIC_EYE))
    distance = np.nan_to_num(np.hypot(floor[..., 0] - CONTACT[0], floor[..., 2] - CONTACT[2]), nan=np.inf)
    region = (distance < radius) & ~dilate(sphere | np.isnan(floor[..., 0]))
    region[[0, -1], :] = region[:, [0, -1]] = False
    return region


PHOTON_INTEGRATORS = ("photonMapFinalGather", "photonMapIrradianceCache")


@pytest.fixture(scope="module")
def caustic_views(caustic_scene):
    """The path tracer's caustic view as two independent 512-spp halves, and each photon integrator's
    (default photon counts, 8 spp)."""
    halves = [render_caustic_view(caustic_scene, "path", 512, seed) for seed in (11, 12)]
    return halves, {name: render_caustic_view(caustic_scene, name, 8, 0) for name in PHOTON_INTEGRATORS}


def energy_ratios(caustic_views, radius):
    region = caustic_region(radius)
    halves = [half[region].mean(0) for half in caustic_views[0]]
    reference = (halves[0] + halves[1]) / 2
    print(f"floor within {radius} of the contact point: {region.sum()} pixels, reference mean RGB "
          f"{np.round(reference, 4)}, halves differ by {np.round(np.abs(halves[0] - halves[1]) / reference, 4)}")
    assert region.sum() >= 50, region.sum()
    # A 512-spp half's mean over either region varies by 1.0-1.5% per channel (over seeds 11-18), so
    # two halves may differ by 4 sigma of their difference, 4 sqrt(2) 1.5% ~ 9%.
    assert (np.abs(halves[0] - halves[1]) < 0.09 * reference).all(), halves
    assert reference[1] > 1.5 * reference[0], reference  # green: the glass's tint
    ratios = {}
    for integrator, image in caustic_views[1].items():
        mean = image[region].mean(0)
        ratios[integrator] = mean / reference
        print(f"{integrator}: mean RGB {np.round(mean, 4)}, ratio to the reference {np.round(ratios[integrator], 3)}")
    return ratios


# The photon integrators' region means (8 spp) over the reference's (two 512-spp halves). Measured
# over seeds 0-5 against a 4096-spp path tracer (seeds 11-18), per channel: within 0.2 of the contact
# point final gathering 1.028-1.030 (sd 1.3-1.4% per seed), the photon cache 1.036-1.038 (sd
# 1.0-1.3%); within 0.4, 1.034-1.039 (sd 0.9-1.2%) and 1.051-1.058 (sd 1.1-1.9%). The reference's
# two halves put 1.0-1.5% / sqrt(2) of noise on the ratio. 4 sigma of a seed's and the reference's
# noise is 7% within 0.2 and 9% within 0.4 (the largest over integrators and channels). The means
# over six seeds show a bias the bounds do not resolve: +3-4% in the caustic, +3.5-5.5% with its halo
# (both integrators carry unbounded depth, as the path tracer; the caustic map's density estimate
# is the lead).
CAUSTIC_BOUNDS = {CAUSTIC_RADIUS: 0.07, SPHERE_RADIUS: 0.09}


def test_caustic_carries_the_reference_energy(caustic_views):
    """Mean radiance of the caustic under the glass sphere, per colour channel, within 4 sigma of
    the path tracer's (default photon counts; CAUSTIC_BOUNDS)."""
    for integrator, ratio in energy_ratios(caustic_views, CAUSTIC_RADIUS).items():
        assert (np.abs(ratio - 1) < CAUSTIC_BOUNDS[CAUSTIC_RADIUS]).all(), (integrator, ratio)


def test_floor_under_the_sphere_carries_the_reference_energy(caustic_views):
    """The whole floor under the sphere (r < 0.4: the caustic and the halo round it) within 4 sigma
    (CAUSTIC_BOUNDS). With a box-filtered caustic estimate it was +11-13%, which the caustic map's
    cone filter (photon_maps.h) cut."""
    for integrator, ratio in energy_ratios(caustic_views, SPHERE_RADIUS).items():
        assert (np.abs(ratio - 1) < CAUSTIC_BOUNDS[SPHERE_RADIUS]).all(), (integrator, ratio)
