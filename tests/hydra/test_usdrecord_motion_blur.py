"""usdrecord through hdGi blurs what moves during the camera's shutter (SampleTransform,
SamplePrimvar of points, the camera's shutter) to the width `gi render` reaches: the scenes,
measure and tolerance of tests/python/test_motion_blur.py.
usdrecord hides dome lights from the camera unless told (--enableDomeLightVisibility); the
measure needs the lit background."""
import sys

import pytest

from conftest import REPO, hdgi_errors, read_rgb, run_openusd

sys.path.insert(0, str(REPO / "tests" / "python"))
from test_motion_blur import (FRAME, RESOLUTION, WIDTH_TOLERANCE, analytic_variance, motion_stage,  # noqa: E402
                              profile_variance, width)


@pytest.mark.parametrize("kind", ["sphere", "quad", "deforming quad"])
def test_usdrecord_blurs_a_moving_object_to_the_analytic_width(tmp_path, kind):
    scene = motion_stage(tmp_path / "moving.usda", kind)
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight", "--enableDomeLightVisibility",
                          "--colorCorrectionMode", "disabled", "--imageWidth", str(RESOLUTION[0]),
                          "--camera", "/Camera", "--frames", str(FRAME), str(scene), str(tmp_path / "moving.####.exr")])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    image = read_rgb(tmp_path / f"moving.{FRAME:04d}.exr")
    assert image.shape[:2] == (RESOLUTION[1], RESOLUTION[0])
    expected = width(analytic_variance(kind))
    assert abs(width(profile_variance(image)) - expected) / expected < WIDTH_TOLERANCE
