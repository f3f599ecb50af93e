"""Time limits are kept (issue 16): every integrator's render, preprocessing included, ends within
5% + 0.2 s of its budget on the Cornell box, whether measured by the render itself or around the call.

About 60 s on two cores: every integrator (auto's pilots included) at 1 and 3 s, and the
slowest-preprocessing integrator and the path tracer at 10 s.
"""
import time

import numpy as np
import pytest

from conftest import CORNELL, run_gi

SIZE = (64, 64)
INTEGRATORS = ["path", "direct", "irradianceCache", "adaptiveIrradianceCache", "photonMapFinalGather",
               "photonMapIrradianceCache", "progressivePhotonMap", "auto"]
# 10 s for the integrator whose preprocessing overran most before (photonMapFinalGather: 3.3 s of
# photon tracing and irradiance precomputation at any budget) and for the path tracer (passes only).
LONG = ["path", "photonMapFinalGather"]
CASES = [(name, 1.0) for name in INTEGRATORS] + [(name, 3.0) for name in INTEGRATORS] + \
        [(name, 10.0) for name in LONG]


def allowed(budget):
    """The issue's bound: within 5% + 0.2 s of the budget, either way (issue 16, item 1)."""
    return 0.05 * budget + 0.2


@pytest.fixture(scope="module")
def loaded():
    from gi.loader import load_stage
    return load_stage(str(CORNELL))


def test_every_integrator_is_covered():
    from gi import _core
    assert sorted(INTEGRATORS) == sorted(info["name"] for info in _core.integrators())


@pytest.mark.parametrize("integrator,budget", CASES, ids=[f"{n}-{b:g}s" for n, b in CASES])
def test_budget_is_kept(loaded, integrator, budget):
    from gi.render import render_loaded, render_settings
    from gi.study import BUDGET_SPP_CAP
    settings = render_settings(loaded, integrator, {}, BUDGET_SPP_CAP, 0, 0, budget, SIZE, "box")
    start = time.perf_counter()
    result = render_loaded(loaded, settings, integrator)
    wall = time.perf_counter() - start
    seconds = result.stats["seconds"]
    assert abs(seconds - budget) <= allowed(budget), (seconds, result.stats)
    assert abs(wall - budget) <= allowed(budget), (wall, result.stats)
    assert result.stats["preprocess_seconds"] <= seconds
    # At least one complete pass, and a finite image: the budget bought an image.
    assert result.spp >= 1
    assert np.isfinite(np.asarray(result.color)).all()
    assert result.stats["non_finite_samples"] == 0  # the film zeroes bad samples: the count shows them


def test_preprocessing_that_would_overrun_scales_down_and_says_so(loaded):
    """photonMapFinalGather's defaults (500 000 + 500 000 photons, irradiance at every 4th) take
    seconds to preprocess; at 1 s they must be cut to half the budget, with a warning and a count."""
    from gi.render import render_loaded, render_settings
    settings = render_settings(loaded, "photonMapFinalGather", {}, 1 << 24, 0, 0, 1.0, SIZE, "box")
    before = len(loaded.scene.warnings())
    result = render_loaded(loaded, settings, "photonMapFinalGather")
    warnings = loaded.scene.warnings()[before:]
    assert result.stats["preprocess_scaled_down"] >= 1
    assert any(w.startswith("time limit: photon mapping traced") for w in warnings), warnings
    assert result.stats["photonsEmitted"] < 500000
    # Half the budget for preprocessing (render.h's kPreprocessShare), plus the one pilot chunk
    # and kd-tree build that are not cut: 0.2 s on two cores.
    assert result.stats["preprocess_seconds"] <= 0.5 + 0.2


def test_irradiance_cache_fill_stops_at_the_deadline(loaded):
    """At a budget far below the fill's time the fill stops between phases and the render
    computes what is missing on the fly. (The box's glass sphere gives the cache a caustic map, whose
    photons are cut at the deadline too: a second scale-down.)"""
    from gi.render import render_loaded, render_settings
    settings = render_settings(loaded, "irradianceCache", {}, 1 << 24, 0, 0, 0.3, (256, 256), "box")
    before = len(loaded.scene.warnings())
    result = render_loaded(loaded, settings, "irradianceCache")
    warnings = loaded.scene.warnings()[before:]
    assert abs(result.stats["seconds"] - 0.3) <= allowed(0.3)
    assert result.stats["preprocess_scaled_down"] >= 1
    assert any("irradiance cache fill stopped after phase" in w for w in warnings), warnings


def test_without_a_time_limit_the_image_is_the_same_every_time(loaded):
    """The deadline machinery is off without a time limit: the same seed and spp, the same bits."""
    from gi.render import render_loaded, render_settings
    images = []
    for _ in range(2):
        settings = render_settings(loaded, "path", {}, 5, 7, 0, 0.0, (32, 32), "box")
        result = render_loaded(loaded, settings, "path")
        assert result.spp == 5 and result.stats["partial_pass_pixels"] == 0
        images.append(np.asarray(result.color))
    assert np.array_equal(images[0], images[1])


def test_gi_render_time_limit_is_kept(tmp_path):
    """`gi render --time-limit`: the render's seconds, written into the EXR, keep the budget."""
    from gi import _core
    exr = tmp_path / "out.exr"
    run_gi("render", CORNELL, "--integrator", "photonMapIrradianceCache", "--time-limit", 1,
           "--spp", 1 << 20, "--resolution", *SIZE, "-o", exr, "--no-png")
    _, meta = _core.read_image(str(exr))
    assert abs(float(meta["gi:seconds"]) - 1.0) <= allowed(1.0), meta
