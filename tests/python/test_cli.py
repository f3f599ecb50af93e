"""The gi command line renders the Cornell box end to end."""
import json

import numpy as np

from conftest import run_gi


def test_render_writes_exr_png_and_summary(cornell, tmp_path):
    out = tmp_path / "cornell.exr"
    proc = run_gi("render", cornell, "--spp", 4, "--resolution", 64, 64, "--path-depth", 5, "--seed", 3, "-o", out)
    assert "Mrays/s" in proc.stdout and "ksamples/s" in proc.stdout
    assert out.exists() and out.with_suffix(".png").exists()
    from gi import _core
    pixels, meta = _core.read_image(str(out))
    assert pixels.shape == (64, 64, 10)  # R G B Z N.XYZ albedo.RGB
    assert meta["channels"][:4] == ["R", "G", "B", "Z"]
    assert np.isfinite(pixels[..., :3]).all()
    assert np.isfinite(pixels).all()  # every layer: pixels that hit nothing get a finite Z too
    # The film zeroes bad samples, so finite pixels alone prove nothing: none may have occurred.
    assert meta["gi:non_finite_samples"] == "0"
    assert "non-finite" not in proc.stderr
    assert meta["gi:integrator"] == "path" and meta["gi:spp"] == "4" and meta["gi:seed"] == "3"
    assert json.loads(meta["gi:params"]) == {"pathDepth": 5}
    png, _ = _core.read_image(str(out.with_suffix(".png")))
    assert png.shape == (64, 64, 3)


def test_flag_of_another_integrator_is_an_error(cornell, tmp_path):
    proc = run_gi("render", cornell, "--integrator", "direct", "--spp", 1, "--resolution", 16, 16,
                  "--path-depth", 3, "-o", tmp_path / "d.exr", "--no-png", check=False)
    assert proc.returncode == 2
    assert "--path-depth is not a parameter of 'direct'" in proc.stderr
    assert not (tmp_path / "d.exr").exists()


def test_help_shows_each_integrators_own_default():
    help_text = " ".join(run_gi("render", "--help").stdout.split())
    # `paths` means camera-hit paths for the path tracer and record paths for the caches.
    assert "path 1" in help_text and "irradianceCache 108" in help_text and "photonMapIrradianceCache 120" in help_text


def test_inspect_lists_what_the_scene_needs(cornell):
    proc = run_gi("inspect", cornell)
    assert "10 triangles" in proc.stdout and "1 exact spheres" in proc.stdout
    assert "1 rect" in proc.stdout and "caustic paths yes" in proc.stdout


def test_every_integrator_renders_finite(cornell):
    from gi import _core
    from conftest import render
    for info in _core.integrators():
        # auto without a time limit plans for its horizon (its pilots take a tenth of it): 1 s here.
        params = {"autoHorizon": 1.0} if info["name"] == "auto" else {}
        img, result, _ = render(cornell, info["name"], spp=2, resolution=(24, 24), **params)
        assert np.isfinite(img).all(), info["name"]
        assert img.mean() > 0.01, info["name"]
        assert result.stats["non_finite_samples"] == 0, info["name"]
