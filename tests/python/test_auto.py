"""`--integrator auto` (issue 16 item 3): pilots choose the technique, the choice is logged and
recorded, the time limit holds pilots included, and where the sun reaches the room only through
glass (the path tracer misses it) the pilots see it and choose a photon technique.
The prediction itself is tested on synthetic pilots in tests/cpp/test_auto.cpp."""
import numpy as np
import pytest

from conftest import CORNELL, ROOT, run_gi

_core = pytest.importorskip("gi._core")
ROOM = ROOT / "scenes" / "window_room" / "window_room.usda"
PHOTON_TECHNIQUES = {"progressivePhotonMap", "photonMapFinalGather", "photonMapIrradianceCache"}


def render_auto(scene, seconds, resolution, **params):
    from gi.render import render_loaded, render_settings
    from gi.loader import load_stage
    from gi.study import BUDGET_SPP_CAP
    loaded = load_stage(str(scene))
    settings = render_settings(loaded, "auto", params, BUDGET_SPP_CAP, 0, 0, seconds, resolution, "box")
    return render_loaded(loaded, settings, "auto")


def test_auto_is_in_the_registry_with_its_candidates():
    names = {info["name"] for info in _core.integrators()}
    assert "auto" in names
    assert set(_core.auto_candidates()) <= names and "direct" not in _core.auto_candidates()


def test_auto_names_its_choice_and_every_prediction():
    result = render_auto(CORNELL, 2.0, (48, 36))
    assert result.integrator in _core.auto_candidates()
    assert result.auto_summary.startswith(f"auto: chose {result.integrator} ")
    for name in _core.auto_candidates():
        assert f" {name} " in result.auto_summary + " ", result.auto_summary
    # The pilots keep their share (autoPilotShare 0.1 of 2 s) within one pilot pass's overshoot.
    assert result.stats["auto_pilot_seconds"] <= 0.1 * 2.0 + 0.2
    assert np.isfinite(np.asarray(result.color)).all() and result.stats["non_finite_samples"] == 0


def test_without_a_time_limit_auto_plans_for_its_horizon():
    from gi.render import render_loaded, render_settings
    from gi.loader import load_stage
    loaded = load_stage(str(CORNELL))
    settings = render_settings(loaded, "auto", {"autoHorizon": 2.0}, 3, 0, 0, 0.0, (32, 24), "box")
    result = render_loaded(loaded, settings, "auto")
    assert result.spp == 3  # the samples asked for, whatever the choice
    assert "for 2 s" in result.auto_summary
    assert result.stats["auto_pilot_seconds"] <= 0.1 * 2.0 + 0.2


def test_the_cli_logs_the_choice_and_records_it_in_the_exr(tmp_path):
    out = tmp_path / "auto.exr"
    proc = run_gi("render", CORNELL, "--integrator", "auto", "--time-limit", 1.5, "--spp", 100000,
                  "--resolution", 32, 24, "-o", out, "--no-png")
    assert "gi: auto: chose " in proc.stderr
    chosen = proc.stderr.split("gi: auto: chose ")[1].split()[0]
    assert f"auto -> {chosen}" in proc.stdout
    _, meta = _core.read_image(str(out))
    assert meta["gi:integrator"] == chosen and meta["gi:auto"].startswith(f"auto: chose {chosen}")


def test_auto_sees_the_sun_through_glass():
    """The glazed room's sun reaches the floor only through the pane: the path tracer finds it about
    once in 10^5 bounces (RMSE 43 against 3-6 for the photon techniques at 10 s, bench/untuned.py).
    Its pilot is dark where the progressive photon map's is lit, so the path tracer's miss counts
    against it and a photon technique must be chosen. Pilots get half of 6 s here, so that every
    technique's pilot completes on a loaded 2-core machine too."""
    result = render_auto(ROOM, 6.0, (128, 96), autoPilotShare=0.5)
    assert result.integrator in PHOTON_TECHNIQUES, result.auto_summary


def test_a_sequence_keeps_the_first_frames_choice(tmp_path):
    # Timed pilots may choose apart from frame to frame; a sequence must not switch techniques.
    out = tmp_path / "auto.####.exr"
    proc = run_gi("render", CORNELL, "--integrator", "auto", "--auto-horizon", 1, "--spp", 1,
                  "--resolution", 32, 24, "--frames", "1-3", "-o", out, "--no-png")
    assert proc.stderr.count("gi: auto: chose ") == 1, proc.stderr
    chosen = proc.stderr.split("gi: auto: chose ")[1].split()[0]
    assert proc.stderr.count(f"gi: auto: kept {chosen}, chosen by an earlier render (no pilots)") == 2
    for frame in (1, 2, 3):
        _, meta = _core.read_image(str(tmp_path / f"auto.{frame:04d}.exr"))
        assert meta["gi:integrator"] == chosen
