"""Metrics on images with known answers (specs/cornell.md section 7)."""
import math

import numpy as np
import pytest

from gi import metrics


def const(value, h=8, w=8):
    """An (h, w, 3) float32 image filled with value (a scalar or an RGB triple)."""
    return np.broadcast_to(np.asarray(value, np.float32), (h, w, 3)).copy()


@pytest.fixture
def ref():
    return np.random.default_rng(1).uniform(0.0, 1.0, (16, 12, 3)).astype(np.float32)


# --- RMSE -------------------------------------------------------------------------------------

def test_rmse_of_identical_images_is_zero(ref):
    assert metrics.rmse_linear(ref, ref) == 0.0
    assert metrics.rmse_srgb8(ref, ref) == 0.0


@pytest.mark.parametrize("c", [0.25, -0.125, 3.0])
def test_rmse_linear_of_constant_offset_is_the_offset(ref, c):
    # No clamping: the offset 3.0 pushes values far above 1 and must still count in full.
    assert metrics.rmse_linear(ref + np.float32(c), ref) == pytest.approx(abs(c), rel=1e-6)


def test_rmse_linear_is_root_of_mean_square_not_mean_abs():
    # Errors of 0 and 1 on half the pixels each: RMSE = sqrt(1/2), mean |e| would be 1/2.
    img = const(0.0)
    img[:4] = 1.0
    assert metrics.rmse_linear(img, const(0.0)) == pytest.approx(math.sqrt(0.5))


@pytest.mark.parametrize("linear, code", [
    (0.0, 0), (-1.0, 0), (0.001, 3), (0.0031308, 10),  # linear segment: 12.92 x
    (0.2, 124), (0.5, 188), (1.0, 255), (7.0, 255),     # power segment and clamping
])
def test_srgb8_codes(linear, code):
    assert metrics.srgb8(const(linear)).dtype == np.uint8
    assert np.all(metrics.srgb8(const(linear)) == code)


@pytest.mark.parametrize("a, b, code_diff", [(0.5, 0.2, 188 - 124), (1.0, 0.0, 255), (2.0, 1.0, 0)])
def test_rmse_srgb8_of_constants_is_code_difference(a, b, code_diff):
    assert metrics.rmse_srgb8(const(a), const(b)) == pytest.approx(code_diff)


def test_relative_mse_known_value():
    # Top half: img 3, ref 2 -> 1 / (4 + 0.01). Bottom half: img 0.1, ref 0 -> 0.01 / 0.01 = 1.
    img, ref = const(3.0), const(2.0)
    img[4:], ref[4:] = 0.1, 0.0
    assert metrics.relative_mse(img, ref) == pytest.approx((1 / 4.01 + 1.0) / 2, rel=1e-6)
    assert metrics.relative_mse(img, ref, eps=1.0) == pytest.approx((1 / 5 + 0.01) / 2, rel=1e-6)


# --- luminance and fireflies ------------------------------------------------------------------

def test_luminance_rec709():
    assert metrics.luminance(const(1.0)) == pytest.approx(np.ones((8, 8)))
    assert metrics.luminance(const([0.0, 1.0, 0.0]))[0, 0] == pytest.approx(0.7152)
    assert metrics.luminance(const([1.0, 0.0, 0.0]))[0, 0] == pytest.approx(0.2126)


def test_luminance_ratio(ref):
    assert metrics.luminance_ratio(2 * ref, ref) == pytest.approx(2.0)
    assert metrics.luminance_ratio(ref, ref) == pytest.approx(1.0)


def smooth_reference(height=32, width=32):
    """A smooth image with a black band and a bright 'light' patch: what a converged render looks like."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    img = np.repeat((0.3 + 0.2 * np.sin(x / 6.0) * np.cos(y / 7.0))[..., None], 3, axis=-1)
    img[20:26] = 0.0          # a shadow that is black in the reference
    img[2:6, 2:6] = 50.0      # a light, 100x its surroundings
    return img


def test_fireflies_are_the_planted_pixels_far_above_the_reference():
    ref = smooth_reference()
    img = ref * np.random.default_rng(2).uniform(0.8, 1.2, ref.shape).astype(np.float32)  # noise
    planted = [(12, 10), (30, 30), (0, 31), (22, 5)]     # (22, 5) sits in the black band
    for p in planted:
        img[p] = 20.0
    img[15, 20] = 2.0      # ~6x the reference there: noise, not a firefly at k = 10
    img[6, 3] = 30.0       # beside the light: its 3x3 neighbourhood includes the light
    assert metrics.firefly_count(img, ref) == len(planted)
    assert metrics.firefly_count(img, ref, k=5.0) == len(planted) + 1


def test_a_smooth_brighter_image_has_no_fireflies():
    ref = smooth_reference()
    assert metrics.firefly_count(ref * 3.0, ref) == 0      # 3x brighter everywhere: wrong, but no fireflies
    assert metrics.firefly_count(ref, ref) == 0
    # Faint noise where the reference is black stays under the floor (a typical lit pixel).
    noisy = ref.copy()
    noisy[20:26] = 0.05
    assert metrics.firefly_count(noisy, ref) == 0


def test_firefly_local_value_is_a_box_mean_with_repeated_edges():
    ref = np.zeros((5, 5, 3), np.float32)
    ref[2, 2] = 9.0
    local = metrics.local_luminance(ref)
    assert local[2, 2] == pytest.approx(1.0) and local[1, 1] == pytest.approx(1.0) and local[0, 0] == 0.0
    assert metrics.local_luminance(const(2.0))[0, 0] == pytest.approx(2.0)


def test_firefly_count_of_black_images_is_zero():
    assert metrics.firefly_count(const(0.0), const(0.0)) == 0
    assert metrics.firefly_count(const(0.0), const(1.0)) == 0


def test_has_nan_or_inf(ref):
    assert not metrics.has_nan_or_inf(ref)
    for bad in (np.nan, np.inf, -np.inf):
        img = ref.copy()
        img[3, 4, 1] = bad
        assert metrics.has_nan_or_inf(img)


# --- difference image -------------------------------------------------------------------------

@pytest.mark.parametrize("t, rgb", [
    (0.0, (0, 0, 0)), (1 / 3, (0, 255, 0)), (2 / 3, (255, 255, 0)), (1.0, (255, 0, 0)),
    (-0.5, (0, 0, 0)), (2.0, (255, 0, 0)),  # clamped outside [0, 1]
])
def test_palette_knots(t, rgb):
    assert tuple(metrics.palette(t)) == rgb


def test_palette_is_piecewise_linear_between_knots():
    # Halfway between knots the exact value is 127.5; rounding may go either way.
    for t, rgb in [(1 / 6, (0, 127.5, 0)), (0.5, (127.5, 255, 0)), (5 / 6, (255, 127.5, 0))]:
        assert np.abs(metrics.palette(t).astype(float) - rgb).max() <= 0.5


def test_difference_image_of_identical_images_is_black(ref):
    diff, max_error = metrics.difference_image(ref, ref)
    assert diff.shape == ref.shape and diff.dtype == np.uint8
    assert not diff.any()
    assert max_error == 1.0


def test_difference_image_colours_by_srgb8_error():
    ref = const(0.0)
    img = ref.copy()
    img[0, 0] = 1.0                  # error 255 on every channel -> red at max_error 255
    img[0, 1] = [1.0, 0.0, 0.0]      # mean over channels 85 = 255 / 3 -> green
    diff, max_error = metrics.difference_image(img, ref, max_error=255)
    assert max_error == 255
    assert tuple(diff[0, 0]) == (255, 0, 0)
    assert tuple(diff[0, 1]) == (0, 255, 0)
    assert not diff[1:].any()


def test_difference_image_default_scale_is_99th_percentile():
    ref = const(0.0, 10, 10)
    img = ref.copy()
    img[:5] = [1.0, 0.0, 0.0]        # half the pixels: error 85
    img[9, 9] = 1.0                  # one outlier: error 255, clipped to red
    diff, max_error = metrics.difference_image(img, ref)
    assert max_error == pytest.approx(np.percentile([0] * 49 + [85] * 50 + [255], 99))
    assert tuple(diff[9, 9]) == (255, 0, 0)


# --- FLIP -------------------------------------------------------------------------------------

def test_flip_of_identical_images_is_zero(ref):
    assert metrics.flip(ref, ref) == 0.0


def test_flip_of_black_against_white_is_large():
    assert metrics.flip(const(0.0, 32, 32), const(1.0, 32, 32)) > 0.5


def test_flip_known_values():
    # Regression values from flip-evaluator 1.7 (LDR, default 67 ppd). They change if the mode,
    # the ppd or the sRGB encoding of the inputs does.
    assert metrics.flip(const(0.5, 32, 32), const(0.2, 32, 32)) == pytest.approx(0.53592, abs=1e-4)
    # A 2-pixel checkerboard against mid grey: the eye's spatial filter at 67 ppd blurs most of
    # it away (at 30 ppd it would be 0.67), so this pins the viewing distance.
    y, x = np.mgrid[0:32, 0:32]
    checker = np.repeat(((x // 2 + y // 2) % 2).astype(np.float32)[..., None], 3, axis=-1)
    assert metrics.flip(checker, const(0.5, 32, 32)) == pytest.approx(0.14284, abs=1e-4)


def test_flip_grows_with_the_error(ref):
    assert 0 < metrics.flip(ref * 0.9, ref) < metrics.flip(ref * 0.5, ref)


# --- compare and input checks -----------------------------------------------------------------

def test_compare_identical(ref):
    m = metrics.compare(ref, ref)
    assert (m.rmse_linear, m.rmse_srgb8, m.relative_mse, m.flip) == (0.0, 0.0, 0.0, 0.0)
    assert m.luminance_ratio == pytest.approx(1.0)
    assert m.fireflies == 0


def test_compare_matches_individual_metrics(ref):
    img = ref * 1.1
    m = metrics.compare(img, ref)
    assert m.rmse_linear == metrics.rmse_linear(img, ref)
    assert m.rmse_srgb8 == metrics.rmse_srgb8(img, ref)
    assert m.luminance_ratio == pytest.approx(1.1)


def test_extra_channels_are_ignored(ref):
    rgba = np.concatenate([ref, np.full(ref.shape[:2] + (1,), 7.0, np.float32)], axis=-1)
    assert metrics.rmse_linear(rgba, ref) == 0.0
    assert metrics.compare(rgba, ref).flip == 0.0


@pytest.mark.parametrize("fn", [metrics.rmse_linear, metrics.rmse_srgb8, metrics.relative_mse,
                                metrics.luminance_ratio, metrics.flip, metrics.compare,
                                lambda a, b: metrics.difference_image(a, b)])
def test_shape_mismatch_raises_naming_both_shapes(fn):
    with pytest.raises(ValueError) as excinfo:
        fn(const(0.5, 8, 8), const(0.5, 8, 6))
    assert "(8, 8, 3)" in str(excinfo.value) and "(8, 6, 3)" in str(excinfo.value)


@pytest.mark.parametrize("shape", [(8, 8), (8, 8, 2), (8, 8, 8, 3)])
def test_non_rgb_shapes_raise(shape):
    with pytest.raises(ValueError):
        metrics.luminance(np.zeros(shape, np.float32))


def test_local_outliers_count_a_splotch_not_noise():
    rng = np.random.default_rng(3)
    ref = np.full((64, 64, 3), 0.5, np.float32)
    noisy = lambda: ref * rng.gamma(4.0, 0.25, size=(64, 64, 1)).astype(np.float32)  # noqa: E731
    a, b = noisy(), noisy()
    sigma = metrics.block_noise(a, b)
    assert metrics.local_outlier_share(noisy(), ref, sigma) == 0
    splotched = noisy()
    splotched[8:16, 24:32] *= 1.5  # one 8x8 block 50% too bright: 64 blocks, one of them
    assert metrics.local_outlier_share(splotched, ref, sigma) == pytest.approx(1 / 64)
