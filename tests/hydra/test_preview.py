"""The interactive preview (hdGi/renderSession.cpp, _RenderPreview): in a view of 256x256 pixels
or more, each render first shows one path-traced sample per pixel at 1/8 of the resolution, then
renders its passes as without it. The preview is never accumulated, so the converged image is
`gi render`'s bit for bit; the render stats put its pixels before the first pass."""
import json

import numpy as np

from conftest import CORNELL, REPO, hdgi_errors, openusd_python, read_rgb, run_openusd, settings_layer
from test_usdrecord import gi_render_scene

STATS = REPO / "tests/hydra/scripts/record_stats.py"


def first_pixels_and_pass(width):
    result = run_openusd([openusd_python(), str(STATS), str(CORNELL), str(width), "path", "2", "0"])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    stats = json.loads(result.stdout.strip().splitlines()[-1])["stats"]
    return stats["firstPixelSeconds"], stats["firstPassSeconds"]


def test_a_large_view_shows_a_preview_before_its_first_pass():
    pixels, first_pass = first_pixels_and_pass(320)
    assert 0 < pixels < first_pass, (pixels, first_pass)
    # A small view has no preview: its first pixels are its first pass's.
    pixels, first_pass = first_pixels_and_pass(128)
    assert 0 < pixels == first_pass, (pixels, first_pass)


def test_auto_keeps_its_preview_after_an_edit():
    # The second render keeps the first one's choice (no pilots); its preview is still path-traced.
    result = run_openusd([openusd_python(), str(STATS), str(CORNELL), "320", "auto:autoHorizon=1", "2", "0", "light"])
    log = result.stdout + result.stderr
    assert not hdgi_errors(log), result.stderr
    assert log.count("hdGi: auto: chose ") == 1, log[-3000:]
    report = json.loads(result.stdout.strip().splitlines()[-1])
    for stats in (report["stats"], report["stats_after_edit"]):
        assert 0 < stats["firstPixelSeconds"] < stats["firstPassSeconds"], stats


def test_the_preview_leaves_the_converged_image_unchanged(tmp_path):
    width, spp, seed = 320, 4, 2
    session = settings_layer(tmp_path / "session.usda", integrator="path", samples=spp, seed=seed)
    output = tmp_path / "preview-hydra.exr"
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--colorCorrectionMode", "disabled", "--imageWidth", str(width), "--camera", "/World/Camera", "--sessionLayer",
                          str(session), str(CORNELL), str(output)])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    hydra = read_rgb(output)
    assert hydra.shape[:2] == (width, width)
    cli = gi_render_scene(tmp_path, CORNELL, "path", spp, seed, width, width)
    assert np.array_equal(hydra, cli)
