"""The path tracer is unbiased: a 4096-spp Cornell box and the mean of 64 independent 64-spp
renders (different seeds) agree within their noise."""
import numpy as np

from conftest import render

RESOLUTION = (32, 32)


def test_long_render_matches_mean_of_independent_short_renders(cornell):
    reference, _, _ = render(cornell, "path", spp=4096, seed=0, resolution=RESOLUTION)
    shorts = np.stack([render(cornell, "path", spp=64, seed=s, resolution=RESOLUTION)[0] for s in range(1, 65)])
    mean_of_shorts = shorts.mean(axis=0)
    # Standard error of the image mean, estimated from the spread of the 64 independent renders.
    image_means = shorts.mean(axis=(1, 2))                       # (64, 3)
    standard_error = image_means.std(axis=0, ddof=1) / np.sqrt(len(shorts))
    difference = reference.mean(axis=(0, 1)) - mean_of_shorts.mean(axis=(0, 1))
    # Both estimates carry about the same noise: allow 4 sigma of their difference.
    assert (np.abs(difference) < 4 * np.sqrt(2) * standard_error + 1e-6).all(), (difference, standard_error)
    # Per pixel the noise is heavy-tailed (caustics through the glass), so a z-score from 64
    # renders under-estimates it. Instead: the long render differs from the mean of the short
    # ones no more than it differs from a second long render with another seed (pure noise).
    second, _, _ = render(cornell, "path", spp=4096, seed=4097, resolution=RESOLUTION)
    to_shorts = np.abs(reference - mean_of_shorts).mean()
    to_second = np.abs(reference - second).mean()
    assert to_shorts < 1.3 * to_second, (to_shorts, to_second)
