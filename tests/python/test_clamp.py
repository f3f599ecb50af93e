"""The opt-in firefly clamp (the sampleClamp parameter every integrator takes; off by default)."""
import numpy as np
import pytest

from conftest import ROOT, render, run_gi

_core = pytest.importorskip("gi._core")
SCENE = ROOT / "scenes" / "stress" / "bright_tiny_light.usda"


def test_every_integrator_takes_sample_clamp_off_by_default():
    for info in _core.integrators():
        param = next(p for p in info["params"] if p["name"] == "sampleClamp")
        assert param["type"] == "float" and param["default"] == 0 and param["min"] == 0


@pytest.mark.parametrize("integrator", ["path", "photonMapFinalGather"])
def test_clamp_bounds_every_pixel_and_is_off_unless_asked(integrator):
    few = {"photons": 5000} if integrator != "path" else {}  # the path tracer takes no photon count
    plain, plain_result, _ = render(SCENE, integrator, spp=8, resolution=(24, 24), **few)
    default, _, _ = render(SCENE, integrator, spp=8, resolution=(24, 24), sampleClamp=0.0, **few)
    assert np.array_equal(plain, default) and plain_result.stats["clamped_samples"] == 0
    limit = 0.5
    clamped, result, _ = render(SCENE, integrator, spp=8, resolution=(24, 24), sampleClamp=limit, **few)
    y = clamped[..., :3] @ np.array([0.2126, 0.7152, 0.0722])
    assert y.max() <= limit * (1 + 1e-5)
    assert result.stats["clamped_samples"] > 0
    assert np.all(clamped <= plain + 1e-6)  # only ever darkens a sample


def test_render_flag(tmp_path):
    proc = run_gi("render", SCENE, "--spp", 2, "--resolution", 8, 8, "--sample-clamp", 2, "-o", tmp_path / "o.exr",
                  "--no-png")
    assert proc.returncode == 0
    assert "--sample-clamp" in run_gi("render", "--help").stdout
