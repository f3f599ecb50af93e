"""gi against an independent reference (issue 19): converged Mitsuba 3 path-traced images of the
Cornell box and of two analytic scenes (tests/data/mitsuba, made by
tests/data/make_mitsuba_references.py from the arrays gi's loader reads; no gi rendering code).

gi renders each scene at default parameters as BATCHES independent renders (seeds 0..BATCHES-1);
both images are averaged over BLOCK x BLOCK pixel blocks (independent pixels, so the block mean's
noise is close to normal even where single pixels are heavy-tailed, as the caustic under the glass
sphere), and every block and channel gets a Z score against both images' standard errors, as
Mitsuba's own render tests do:
    z = (gi - mitsuba) / sqrt(se_gi^2 + se_mitsuba^2)
gi's standard error comes from the spread of its batches, Mitsuba's from the stored per-pixel
standard error (64 batches). With estimated variances z follows Welch's t, whose degrees of freedom
are at least min(BATCHES, 64) - 1, and a t with fewer degrees of freedom has heavier tails: so the
threshold is the two-sided Student t quantile at that minimum, Bonferroni-corrected over all blocks
and channels for a false-alarm rate of FALSE_ALARM per scene."""
import json
import math

import numpy as np
import pytest

from conftest import ROOT

DATA = ROOT / "tests" / "data" / "mitsuba"
SCENES = ["cornell", "dome_sphere", "glossy_plane", "sun_plane"]
BATCHES = 32          # gi renders per scene, one seed each
# Samples per pixel of each gi render. The Cornell box's caustics (light reaching the walls through
# and off the glass sphere) come from rare, bright samples, so a block's mean is skewed low and the
# batches' spread under-estimates its noise until there are many samples. Measured (gi mean /
# Mitsuba mean 1.0001-1.0003 throughout): 32 x 32 spp, 8x8 blocks: |z| to 8.3, 10 of 108 beyond 3;
# 32 x 128 spp: to 4.95; 32 x 256 spp: 8x8 blocks to 4.3 (15 of 108 beyond 2, 5 expected),
# 16x16 blocks to 3.1 (2 of 27 beyond 2), against a threshold of 4.8. The z shrinking as samples
# grow is the mark of noise, not of a bias (which would make it grow).
SPP = {"cornell": 256, "dome_sphere": 32, "glossy_plane": 32, "sun_plane": 32}
BLOCK = 16            # pixels per block side (48x48 -> 9 blocks, 27 Z scores with the channels)
FALSE_ALARM = 1e-3    # per scene, over all its blocks and channels (Bonferroni)


def t_two_sided_tail(x, dof):
    """P(|T| > x) for Student's t: the regularized incomplete beta I_z(dof/2, 1/2) at
    z = dof / (dof + x^2), integrated numerically (the integrand is smooth on [0, z], z < 1)."""
    a, b = dof / 2, 0.5
    z = dof / (dof + x * x)
    s = np.linspace(0.0, z, 200_001)
    log_beta = math.lgamma(a) + math.lgamma(b) - math.lgamma(a + b)
    integrand = np.exp((a - 1) * np.log(np.maximum(s, 1e-300)) + (b - 1) * np.log1p(-s) - log_beta)
    return float(np.sum((integrand[1:] + integrand[:-1]) / 2) * (s[1] - s[0]))


def t_threshold(p, dof):
    """x with P(|T| > x) = p (bisection; the tail falls monotonically)."""
    low, high = 0.0, 100.0
    for _ in range(60):
        middle = (low + high) / 2
        low, high = (middle, high) if t_two_sided_tail(middle, dof) > p else (low, middle)
    return high


def test_t_threshold_matches_known_quantiles():
    # Tables: t(10) two-sided 5% = 2.228; t(30) two-sided 0.1% = 3.646.
    assert t_threshold(0.05, 10) == pytest.approx(2.228, abs=2e-3)
    assert t_threshold(0.001, 30) == pytest.approx(3.646, abs=2e-3)


def blocks(images):
    """(..., H, W, 3) -> (..., H/BLOCK, W/BLOCK, 3) block means."""
    *lead, height, width, channels = images.shape
    shaped = images.reshape(*lead, height // BLOCK, BLOCK, width // BLOCK, BLOCK, channels)
    return shaped.mean(axis=(-4, -2))


def gi_batches(scene_path, resolution, spp, params=None):
    import gi
    from gi.render import render_loaded, render_settings
    loaded = gi.load_stage(str(scene_path))
    images = []
    for seed in range(BATCHES):
        settings = render_settings(loaded, "path", dict(params or {}), spp, seed, 0, 0.0, resolution, "box")
        images.append(np.asarray(render_loaded(loaded, settings, "path").color, np.float64)[..., :3])
    return np.stack(images)


def z_scores(name, params=None):
    from gi import _core
    meta = json.loads((DATA / "references.json").read_text())[name]
    reference = np.asarray(_core.read_image(str(DATA / f"{name}.exr"))[0], np.float64)[..., :3]
    reference_se = np.asarray(_core.read_image(str(DATA / f"{name}_se.exr"))[0], np.float64)[..., :3]
    ours = blocks(gi_batches(ROOT / meta["scene"], tuple(meta["resolution"]), SPP[name], params))
    ours_mean, ours_se = ours.mean(axis=0), ours.std(axis=0, ddof=1) / math.sqrt(BATCHES)
    # Pixels are independent: the block mean's variance is the mean of the pixel variances / n.
    reference_block_se = np.sqrt(blocks(reference_se ** 2) / BLOCK ** 2)
    difference = ours_mean - blocks(reference)
    # Where neither image has noise (the dome seen directly) the two differ only by float rounding
    # (Mitsuba's environment map interpolates: 1.3e-6 relative measured): 1e-5 relative stands for it.
    rounding = 1e-5 * np.abs(blocks(reference))
    total_se = np.sqrt(ours_se ** 2 + reference_block_se ** 2 + rounding ** 2)
    dof = min(BATCHES, meta["batches"]) - 1
    z = difference / np.maximum(total_se, 1e-30)
    return z, dof, ours_mean.mean() / blocks(reference).mean()


@pytest.mark.parametrize("name", SCENES)
def test_gi_agrees_with_mitsuba_reference(name):
    z, dof, mean_ratio = z_scores(name)
    threshold = t_threshold(FALSE_ALARM / z.size, dof)
    worst = np.unravel_index(np.argmax(np.abs(z)), z.shape)
    assert np.abs(z).max() < threshold, (
        f"{name}: block {worst[:2]} channel {worst[2]} z = {z[worst]:.2f} beyond {threshold:.2f} "
        f"(gi mean / Mitsuba mean {mean_ratio:.4f}; {int((np.abs(z) >= threshold).sum())} of {z.size} blocks)")
