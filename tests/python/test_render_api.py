"""gi.render is the Python render API: the commands, bench/ and the tests render through it, and
it needs nothing of the command line (issue: an import cycle cli <-> study/reference)."""
import subprocess
import sys

import numpy as np


def test_render_api_does_not_import_the_command_line():
    # A fresh interpreter: this test process has imported gi.cli through other tests.
    code = ("import sys, gi.render, gi.study, gi.reference, gi.render_command, gi.denoise; "
            "print(sorted(m for m in sys.modules if m == 'gi.cli'))")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    assert out.strip() == "[]"


def test_render_scene_renders_a_stage(tmp_path):
    from gi.render import render_scene
    stage = tmp_path / "plane.usda"
    stage.write_text("""#usda 1.0
(
    upAxis = "Y"
)
def Mesh "Floor"
{
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-1, 0, -1), (-1, 0, 1), (1, 0, 1), (1, 0, -1)]
}
def DomeLight "Sky"
{
    float inputs:intensity = 1
}
def Camera "Camera"
{
    double3 xformOp:translate = (0, 1, 3)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
""")
    result, loaded, settings = render_scene(str(stage), "path", spp=4, resolution=(16, 12))
    color = np.asarray(result.color, np.float32)[..., :3]
    assert color.shape == (12, 16, 3) and np.isfinite(color).all()
    assert result.stats["non_finite_samples"] == 0
    # Sky pixels (the floor lies below the horizon line) see the dome's radiance, 1 (no texture).
    assert abs(float(color[0].mean()) - 1.0) < 1e-3
