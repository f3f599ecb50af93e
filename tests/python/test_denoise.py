"""`gi render --denoise` (Intel Open Image Denoise through gi._core.Denoiser) on the Cornell box, and
what happens without Open Image Denoise."""
import numpy as np
import pytest

from conftest import CORNELL, render, run_gi

# 128x128: at 64x64 the box's features are a few pixels wide and OIDN gains less (FLIP ratio 0.73-0.89
# over three seeds against a 16384-spp reference); the reference costs ~20 s of the test's time.
SIZE = (128, 128)
NOISY_SPP = 16
REFERENCE_SPP = 1024


def oidn_or_skip():
    from gi.denoise import open_denoiser
    from gi.errors import DenoiserMissing
    try:
        return open_denoiser()
    except DenoiserMissing as error:
        pytest.skip(f"Open Image Denoise is not installed: {error}")


@pytest.fixture(scope="module")
def reference():
    """The converged Cornell box at SIZE (another seed than the renders it judges)."""
    color, _, _ = render(CORNELL, "path", spp=REFERENCE_SPP, seed=99, resolution=SIZE)
    return color


@pytest.fixture(scope="module")
def denoised_render(tmp_path_factory):
    """`gi render --denoise` at 16 spp: its EXR's channels and metadata."""
    oidn_or_skip()
    from gi import _core
    exr = tmp_path_factory.mktemp("denoise") / "cornell.exr"
    proc = run_gi("render", CORNELL, "--spp", NOISY_SPP, "--resolution", *SIZE, "--seed", 3, "-o", exr, "--denoise")
    pixels, meta = _core.read_image(str(exr))
    channels = meta["channels"]

    def layer(names):
        return np.ascontiguousarray(pixels[..., [channels.index(n) for n in names]], dtype=np.float32)
    return {"denoised": layer(["R", "G", "B"]), "noisy": layer(["noisy.R", "noisy.G", "noisy.B"]),
            "meta": meta, "png": exr.with_suffix(".png"), "stdout": proc.stdout}


def test_denoising_the_16_spp_cornell_box_lowers_its_error(denoised_render, reference):
    """Bounds measured over seeds 3-10 of the 16-spp render against this reference (README, "Denoising"):
    denoised/noisy FLIP 0.66-0.74 (mean 0.699, sd 0.031), RMSE sRGB8 0.43-0.51 (mean 0.459, sd 0.023),
    luminance ratio 0.983-0.993 (mean 0.987, sd 0.0033); each bound is the mean -/+ 4 sd. The issue asked
    for half the FLIP: OIDN does not get there at this size (0.62-0.72 even against a 4096-spp
    reference; 0.56-0.60 at 256x256, whose converged reference would take the test 20 minutes), since FLIP at 67 ppd already discounts pixel-scale noise and the caustic under the glass
    sphere is fireflies at 16 spp that no denoiser can place."""
    from gi import metrics
    denoised, noisy = denoised_render["denoised"], denoised_render["noisy"]
    assert not metrics.has_nan_or_inf(denoised)
    noisy_flip, denoised_flip = metrics.flip(noisy, reference), metrics.flip(denoised, reference)
    noisy_rmse, denoised_rmse = metrics.rmse_srgb8(noisy, reference), metrics.rmse_srgb8(denoised, reference)
    print(f"against {REFERENCE_SPP} spp: FLIP noisy {noisy_flip:.4f}, denoised {denoised_flip:.4f}; "
          f"RMSE sRGB8 noisy {noisy_rmse:.2f}, denoised {denoised_rmse:.2f}")
    assert denoised_flip < 0.823 * noisy_flip
    assert denoised_rmse < 0.55 * noisy_rmse
    assert 0.974 < metrics.luminance_ratio(denoised, reference) < 1.001


def test_raw_layer_is_the_render_without_denoising(denoised_render):
    color, _, _ = render(CORNELL, "path", spp=NOISY_SPP, seed=3, resolution=SIZE)
    # The EXR holds 32-bit floats and renders are deterministic given the seed: bit-identical.
    np.testing.assert_array_equal(denoised_render["noisy"], color)
    assert not np.array_equal(denoised_render["denoised"], denoised_render["noisy"])


def test_metadata_and_png_say_it_was_denoised(denoised_render):
    from gi import _core
    meta = denoised_render["meta"]
    denoiser = oidn_or_skip()
    assert meta["gi:denoised"].startswith(f"Open Image Denoise {denoiser.version} RT filter (hdr)")
    assert float(meta["gi:denoise_seconds"]) > 0
    assert f"OIDN {denoiser.version}" in denoised_render["stdout"]
    # The PNG shows the denoised colour, not the raw one.
    from matplotlib import image as mpimg
    png = mpimg.imread(denoised_render["png"])[..., :3]
    expected = _core.display_transform(denoised_render["denoised"])
    raw = _core.display_transform(denoised_render["noisy"])
    assert np.abs(png - expected).max() <= 1.5 / 255 < np.abs(png - raw).max()


def test_auxiliary_images_guide_the_denoiser(reference):
    """Albedo and normal must reach OIDN: without them (zeros) it blurs the box's edges, so its FLIP is
    higher than the guided result (measured: see README)."""
    from gi import metrics
    from gi.render import render_scene
    denoiser = oidn_or_skip()
    result, _, _ = render_scene(str(CORNELL), "path", {}, NOISY_SPP, 3, resolution=SIZE)
    guided = denoiser.denoise(np.asarray(result.color), np.asarray(result.albedo), np.asarray(result.normal))
    zeros = np.zeros_like(np.asarray(result.albedo))
    unguided = denoiser.denoise(np.asarray(result.color), zeros, zeros)
    assert metrics.flip(guided, reference) < metrics.flip(unguided, reference)


def test_denoise_without_open_image_denoise_is_a_clear_error(tmp_path, monkeypatch):
    # GI_OIDN_LIBRARY, when set, is the only place searched: pointing it nowhere is a machine without OIDN.
    monkeypatch.setenv("GI_OIDN_LIBRARY", str(tmp_path / "nowhere" / "libOpenImageDenoise.so.2"))
    exr = tmp_path / "out.exr"
    proc = run_gi("render", CORNELL, "--spp", 1, "--resolution", 8, 8, "-o", exr, "--denoise", check=False)
    assert proc.returncode == 2, proc.stderr
    assert "gi: error: denoising needs Intel Open Image Denoise 2.x" in proc.stderr
    assert "pip install pyoidn" in proc.stderr and str(tmp_path / "nowhere") in proc.stderr
    assert not exr.exists()  # it fails before rendering
    # Without --denoise nothing changes.
    proc = run_gi("render", CORNELL, "--spp", 1, "--resolution", 8, 8, "-o", exr)
    assert exr.exists()
