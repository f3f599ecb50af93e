"""Image comparison metrics (specs/cornell.md section 7) and the thesis's difference image.

All functions take linear RGB float arrays shaped (H, W, C) with C >= 3; only the first three
channels are used, so RGBA renders can be passed as they are. Sums are done in float64 so that
512x512 means do not lose precision in float32.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Rec.709 / sRGB primaries, applied to linear RGB (spec section 7).
_REC709_Y = np.array([0.2126, 0.7152, 0.0722])

# Difference-image palette knots (thesis figure 3.12): black -> green -> yellow -> red in thirds.
_PALETTE_T = np.array([0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0])
_PALETTE_RGB = np.array([[0, 0, 0], [0, 255, 0], [255, 255, 0], [255, 0, 0]], dtype=np.float64)


def _rgb(img) -> np.ndarray:
    """The first three channels of an (H, W, C>=3) image as float64."""
    a = np.asarray(img)
    if a.ndim != 3 or a.shape[2] < 3:
        raise ValueError(f"expected an (H, W, C>=3) image, got shape {a.shape}")
    return a[..., :3].astype(np.float64)


def _pair(img, ref) -> tuple[np.ndarray, np.ndarray]:
    """Both images as (H, W, 3) float64, after checking that their sizes agree."""
    a, b = _rgb(img), _rgb(ref)
    if a.shape != b.shape:
        raise ValueError(f"image shape {np.shape(img)} does not match reference shape {np.shape(ref)}")
    return a, b


def rmse_linear(img, ref) -> float:
    """RMSE over all pixels and channels of the raw linear floats (no clamping)."""
    a, b = _pair(img, ref)
    return float(np.sqrt(np.mean((a - b) ** 2)))


def relative_mse(img, ref, eps: float = 1e-2) -> float:
    """Mean of (img - ref)^2 / (ref^2 + eps); eps keeps black reference pixels from dominating."""
    a, b = _pair(img, ref)
    return float(np.mean((a - b) ** 2 / (b ** 2 + eps)))


def _srgb_oetf(x: np.ndarray) -> np.ndarray:
    """The sRGB transfer function on values already clamped to [0, 1]."""
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def srgb_encode(img) -> np.ndarray:
    """Linear RGB on the display scale, unrounded: clamp to [0, 1], OETF (0..1)."""
    # NaN has no place on a display scale; show it as black (has_nan_or_inf reports it).
    x = np.clip(np.nan_to_num(_rgb(img), nan=0.0), 0.0, 1.0)
    return _srgb_oetf(x)


def srgb8(img) -> np.ndarray:
    """8-bit sRGB codes: clamp to [0, 1], OETF, * 255, round (spec section 7)."""
    return np.rint(srgb_encode(img) * 255.0).astype(np.uint8)


def rmse_srgb8(img, ref) -> float:
    """RMSE on the 0..255 sRGB codes: the form of the thesis's RMSE tables (eq. 3.1)."""
    a, b = _pair(img, ref)
    return rmse_linear(srgb8(a).astype(np.float64), srgb8(b).astype(np.float64))


def luminance(img) -> np.ndarray:
    """Rec.709 luminance Y of linear RGB, shaped (H, W)."""
    return _rgb(img) @ _REC709_Y


def luminance_ratio(img, ref) -> float:
    """mean(Y(img)) / mean(Y(ref)): 1 when the image carries the right total energy."""
    a, b = _pair(img, ref)
    with np.errstate(divide="ignore", invalid="ignore"):  # a black reference gives inf / nan
        return float(np.mean(luminance(a)) / np.mean(luminance(b)))


def flip(img, ref) -> float:
    """Mean LDR-FLIP (flip-evaluator, its default 67 ppd) between the 8-bit sRGB images."""
    import flip_evaluator  # imported here so the other metrics work without it

    a, b = _pair(img, ref)
    # LDR-FLIP wants sRGB-encoded float32 in [0, 1]; use the same quantised images as rmse_srgb8.
    test = np.ascontiguousarray(srgb8(a), dtype=np.float32) / 255.0
    reference = np.ascontiguousarray(srgb8(b), dtype=np.float32) / 255.0
    # Note the argument order: reference first. A fresh parameters dict means "FLIP's defaults".
    _, mean_error, _ = flip_evaluator.evaluate(reference, test, "LDR", inputsRGB=True,
                                               applyMagma=False, computeMeanError=True,
                                               parameters={})
    return float(mean_error)


FIREFLY_K = 10.0
FIREFLY_WINDOW = 3  # the reference's local value: its luminance averaged over 3x3 pixels


def local_luminance(ref, window: int = FIREFLY_WINDOW) -> np.ndarray:
    """The luminance of ref averaged over a window x window box around every pixel (edges
    repeated), shaped (H, W)."""
    y = luminance(ref)
    r = window // 2
    padded = np.pad(y, r, mode="edge")
    height, width = y.shape
    total = np.zeros_like(y)
    for dy in range(window):
        for dx in range(window):
            total += padded[dy:dy + height, dx:dx + width]
    return total / (window * window)


def firefly_count(img, ref, k: float = FIREFLY_K, window: int = FIREFLY_WINDOW) -> int:
    """Fireflies of img against the reference ref: pixels whose luminance exceeds k times the
    reference's local luminance (its mean over window x window pixels, so that a pixel on the edge
    of a light or a highlight is compared with the light it sits beside). The local value is
    floored at 1/k of the reference's median lit (Y > 0) local luminance, so that where the
    reference is black a pixel counts only when it is brighter than a typical lit pixel, and
    noise in a dark corner does not count everything. A render that is merely brighter
    everywhere (by less than k) has none; an image scored against itself has none."""
    a, b = _pair(img, ref)
    y = luminance(a)
    local = local_luminance(b, window)
    lit = local[local > 0]
    if lit.size == 0:
        # A black reference: anything lit is k x above nothing; count against the image's own scale.
        lit_y = y[y > 0]
        return int(np.count_nonzero(y > k * np.median(lit_y))) if lit_y.size else 0
    floor = float(np.median(lit)) / k
    return int(np.count_nonzero(y > k * np.maximum(local, floor)))


def has_nan_or_inf(img) -> bool:
    """True if any RGB value is NaN or infinite."""
    return not bool(np.isfinite(_rgb(img)).all())


def palette(t) -> np.ndarray:
    """Difference-image colour for t in [0, 1]: uint8 RGB, shaped t.shape + (3,)."""
    t = np.clip(np.asarray(t, dtype=np.float64), 0.0, 1.0)
    rgb = np.stack([np.interp(t, _PALETTE_T, _PALETTE_RGB[:, c]) for c in range(3)], axis=-1)
    return np.rint(rgb).astype(np.uint8)


def _default_max_error(err: np.ndarray) -> float:
    """The 99th percentile, so a few outliers do not wash the rest of the image to black."""
    m = float(np.percentile(err, 99))
    if m <= 0:  # under 1% of pixels differ: scale to the largest error so they still show
        m = float(err.max())
    return m if m > 0 else 1.0


def difference_image(img, ref, max_error: float | None = None) -> tuple[np.ndarray, float]:
    """Thesis-style difference image and the error that maps to red.

    The per-pixel error is the mean over channels of |sRGB8(img) - sRGB8(ref)| (0..255), the
    measure behind the thesis's tables; it is coloured black (0) -> green -> yellow -> red
    (max_error and above).
    """
    a, b = _pair(img, ref)
    err = np.mean(np.abs(srgb8(a).astype(np.float64) - srgb8(b).astype(np.float64)), axis=-1)
    if max_error is None:
        max_error = _default_max_error(err)
    elif not max_error > 0:
        raise ValueError(f"max_error must be positive, got {max_error}")
    return palette(err / max_error), float(max_error)


@dataclass
class Metrics:
    rmse_linear: float
    rmse_srgb8: float
    relative_mse: float
    flip: float
    luminance_ratio: float
    fireflies: int  # pixels of img above FIREFLY_K x the reference's local luminance (firefly_count)


def compare(img, ref) -> Metrics:
    """Every section-7 metric of img against the reference ref."""
    a, b = _pair(img, ref)
    return Metrics(
        rmse_linear=rmse_linear(a, b),
        rmse_srgb8=rmse_srgb8(a, b),
        relative_mse=relative_mse(a, b),
        flip=flip(a, b),
        luminance_ratio=luminance_ratio(a, b),
        fireflies=firefly_count(a, b),
    )


# -- local outliers (splotches) ------------------------------------------------------------------

OUTLIER_BLOCK = 8
OUTLIER_Z = 4.0


def _block_means(img, block: int) -> np.ndarray:
    y = luminance(img)
    h, w = (y.shape[0] // block) * block, (y.shape[1] // block) * block
    return y[:h, :w].reshape(h // block, block, w // block, block).mean(axis=(1, 3))


def block_noise(path_a, path_b, block: int = OUTLIER_BLOCK) -> np.ndarray:
    """Per-block standard deviation of a path-traced image's block means, from two renders that
    differ only in their seed: the relative spread of (a - b) / (a + b) over all blocks, pooled
    (one block pair alone says little), times each block's mean."""
    a, b = _block_means(path_a, block), _block_means(path_b, block)
    mean = 0.5 * (a + b)
    lit = mean > 1e-6
    relative = np.where(lit, (a - b) / np.where(lit, 2 * mean, 1), 0.0)
    # Var(a - b) = 2 sigma^2, so sigma / mean = std((a - b) / (2 mean)) * sqrt(2).
    sigma = float(np.sqrt(np.mean(relative[lit] ** 2)) * np.sqrt(2)) if lit.any() else 0.0
    return sigma * mean


def local_outlier_share(img, ref, sigma_blocks, block: int = OUTLIER_BLOCK, z: float = OUTLIER_Z) -> float:
    """Share of block x block regions whose mean luminance differs from the reference's by more
    than z times the path tracer's block noise (block_noise): splotches of an irradiance cache,
    leaks or dark patches, which a mean or an RMSE averages away. A path tracer at the spp the
    noise was measured at scores about 0 (a 4-sigma block is 1 in 16,000)."""
    d = np.abs(_block_means(img, block) - _block_means(ref, block))
    return float(np.mean(d > z * np.maximum(sigma_blocks, 1e-9)))
