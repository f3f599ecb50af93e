"""usdrecord through hdGi blurs what moves during the camera's shutter (SampleTransform of gprims,
cameras and lights, SamplePrimvar of points, the camera's shutter) to the width `gi render`
reaches: the scenes, measure and tolerance of tests/python/test_motion_blur.py.
usdrecord hides dome lights from the camera unless told (--enableDomeLightVisibility); the
measure needs the lit background.

Not here, because OpenUSD 24.11's scene indices do not hand them over: a native instance's own
motion (UsdImagingNiInstanceAggregationSceneIndex samples instance transforms at the frame only)
and a point instancer moved by velocities alone (its positions authored once); a point instancer
whose positions are time-sampled blurs, as tested."""
import sys

import numpy as np
import pytest

from conftest import REPO, hdgi_errors, openusd_python, read_rgb, run_openusd

sys.path.insert(0, str(REPO / "tests" / "python"))
from test_motion_blur import (FRAME, RESOLUTION, SHUTTER, TRAVEL, WIDTH_TOLERANCE, analytic_variance,  # noqa: E402
                              motion_stage, profile_variance, width)


def animated_point_instancer(path):
    """The point instancer scene with its positions time-sampled one frame either side (as the
    other kinds' transforms) instead of a velocity."""
    from pxr import Gf, Usd, UsdGeom
    motion_stage(path, "point instancer")
    stage = Usd.Stage.Open(str(path))
    instancer = UsdGeom.PointInstancer(stage.GetPrimAtPath("/Object"))
    instancer.GetVelocitiesAttr().Clear()
    positions = instancer.GetPositionsAttr()
    positions.Clear()
    span = SHUTTER[1] - SHUTTER[0]
    for frame, dx in {FRAME - 1: -TRAVEL / span, FRAME + 1: TRAVEL / span}.items():
        positions.Set([Gf.Vec3f(dx, 0, 0)], frame)
    stage.Save()
    return path


@pytest.mark.parametrize("kind", ["sphere", "quad", "deforming quad", "animated point instancer", "camera",
                                  "sphere light", "rect light"])
def test_usdrecord_blurs_a_moving_object_to_the_analytic_width(tmp_path, kind):
    if kind == "animated point instancer":
        scene, kind = animated_point_instancer(tmp_path / "moving.usda"), "point instancer"
    else:
        scene = motion_stage(tmp_path / "moving.usda", kind)
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight", "--enableDomeLightVisibility",
                          "--colorCorrectionMode", "disabled", "--imageWidth", str(RESOLUTION[0]),
                          "--camera", "/Camera", "--frames", str(FRAME), str(scene), str(tmp_path / "moving.####.exr")])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    image = read_rgb(tmp_path / f"moving.{FRAME:04d}.exr")
    assert image.shape[:2] == (RESOLUTION[1], RESOLUTION[0])
    expected = width(analytic_variance(kind))
    assert abs(width(profile_variance(image, kind)) - expected) / expected < WIDTH_TOLERANCE


def test_a_shutter_edit_resamples_the_motion(tmp_path):
    """In one session (one render index) the shutter opens, then closes again: the sphere is sharp
    (its motion sampled at the frame only), then blurred to the analytic width (hdGi's camera
    marked every rprim to sample its motion over the new interval), then sharp as at first, bit
    for bit."""
    scene = motion_stage(tmp_path / "moving.usda", "sphere")
    script = REPO / "tests/hydra/scripts/record_shutter_edit.py"
    shutters = ["0:0", f"{SHUTTER[0]}:{SHUTTER[1]}", "0:0"]
    result = run_openusd([openusd_python(), str(script), str(scene), str(tmp_path), str(FRAME), str(RESOLUTION[0]),
                          *shutters])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    sharp, blurred, again = (read_rgb(tmp_path / f"{i}.exr") for i in range(3))
    still = width(analytic_variance("sphere", travel_px=0))
    assert abs(width(profile_variance(sharp)) - still) / still < WIDTH_TOLERANCE
    expected = width(analytic_variance("sphere"))
    assert abs(width(profile_variance(blurred)) - expected) / expected < WIDTH_TOLERANCE
    assert np.array_equal(sharp, again)
