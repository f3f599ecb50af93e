"""Instancing and subdivision through Hydra: a PointInstancer's instances render as `gi render`
renders them (the same image, up to noise), and a Catmull-Clark mesh is refined with OpenSubdiv
to the host's complexity (usdrecord --complexity) and not refined at the lowest one."""
import numpy as np

from conftest import hdgi_errors, read_rgb, run_openusd
from test_usdrecord import gi_render_scene

SCENE = """#usda 1.0
(
    upAxis = "Y"
)
def Xform "World"
{
    def Camera "Camera"
    {
        float focalLength = 35
        float horizontalAperture = 36
        float verticalAperture = 36
        double3 xformOp:translate = (0, 1.5, 9)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def DistantLight "Sun"
    {
        float inputs:intensity = 3
        bool inputs:normalize = 1
        float3 xformOp:rotateXYZ = (-50, 30, 0)
        uniform token[] xformOpOrder = ["xformOp:rotateXYZ"]
    }
    def DomeLight "Sky"
    {
        float inputs:intensity = 0.3
    }
    def Mesh "Ground"
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-20, 0, -20), (-20, 0, 20), (20, 0, 20), (20, 0, -20)]
        uniform token subdivisionScheme = "none"
        color3f[] primvars:displayColor = [(0.5, 0.5, 0.5)]
    }
    def PointInstancer "Crowd"
    {
        point3f[] positions = [(-3, 0.5, 0), (-1, 0.5, -1), (1, 0.5, 0), (3, 0.5, -1)]
        quath[] orientations = [(1, 0, 0, 0), (0.924, 0, 0.383, 0), (1, 0, 0, 0), (0.707, 0.707, 0, 0)]
        float3[] scales = [(1, 1, 1), (0.5, 1.5, 0.5), (1, 1, 1), (0.8, 0.8, 0.8)]
        int[] protoIndices = [0, 1, 0, 1]
        rel prototypes = [</World/Crowd/Box>, </World/Crowd/Ball>]
        def Mesh "Box"
        {
            int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
            int[] faceVertexIndices = [0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4]
            point3f[] points = [(-0.5, -0.5, 0.5), (0.5, -0.5, 0.5), (-0.5, 0.5, 0.5), (0.5, 0.5, 0.5), (-0.5, 0.5, -0.5), (0.5, 0.5, -0.5), (-0.5, -0.5, -0.5), (0.5, -0.5, -0.5)]
            uniform token subdivisionScheme = "none"
            color3f[] primvars:displayColor = [(0.8, 0.2, 0.2)]
        }
        def Sphere "Ball"
        {
            double radius = 0.5
            color3f[] primvars:displayColor = [(0.2, 0.3, 0.8)]
        }
    }
    def Mesh "Smooth"
    {
        int[] faceVertexCounts = [4, 4, 4, 4, 4, 4]
        int[] faceVertexIndices = [0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6, 6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4]
        point3f[] points = [(-0.5, -0.5, 0.5), (0.5, -0.5, 0.5), (-0.5, 0.5, 0.5), (0.5, 0.5, 0.5), (-0.5, 0.5, -0.5), (0.5, 0.5, -0.5), (-0.5, -0.5, -0.5), (0.5, -0.5, -0.5)]
        uniform token subdivisionScheme = "catmullClark"
        color3f[] primvars:displayColor = [(0.2, 0.8, 0.3)]
        double3 xformOp:translate = (0, 2.2, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
}
"""


def usdrecord(scene, output, complexity="low", integrator="direct", samples=4):
    session = output.with_suffix(".session.usda")
    session.write_text('#usda 1.0\ndef Scope "Render"\n{\n    def RenderSettings "Gi"\n    {\n'
                       f'        custom string gi:integrator = "{integrator}"\n'
                       f'        custom int gi:samples = {samples}\n    }}\n}}\n')
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight", "--enableDomeLightVisibility",
                          "--colorCorrectionMode", "disabled", "--imageWidth", "160", "--camera", "/World/Camera",
                          "--complexity", complexity, "--renderSettingsPrimPath", "/Render/Gi", "--sessionLayer",
                          str(session), str(scene), str(output)])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    return read_rgb(output)


def test_instances_and_subdivision(tmp_path):
    scene = tmp_path / "geometry.usda"
    scene.write_text(SCENE)
    low = usdrecord(scene, tmp_path / "low.exr")
    high = usdrecord(scene, tmp_path / "high.exr", complexity="high")
    assert np.isfinite(low).all() and np.isfinite(high).all()
    # Refinement rounds the green cube: its silhouette changes (and so do its shadow and the sky
    # it hides from the ground).
    changed = np.abs(high - low).max(axis=-1) > 1e-3
    print(f"refinement changed {changed.sum()} pixels")
    assert changed.sum() > 50


def test_instancer_scene_matches_gi_render(tmp_path):
    scene = tmp_path / "geometry.usda"
    scene.write_text(SCENE)
    # Without refinement Hydra's image is gi render's up to noise (the two front ends list the
    # sun and the sky in a different order, so light selection draws differ): instances in the
    # same places, the same size and orientation, compared in 8x8-pixel blocks.
    hydra = usdrecord(scene, tmp_path / "low64.exr", samples=64)
    cli = gi_render_scene(tmp_path, scene, "direct", 64, 0, 160, 160)
    blocks = lambda a: a.reshape(20, 8, 20, 8, 3).mean(axis=(1, 3))  # noqa: E731
    difference = np.abs(blocks(hydra) - blocks(cli)).max()
    print(f"means {hydra.mean():.4f} / {cli.mean():.4f}; largest 8x8 block difference {difference:.4f}")
    assert abs(hydra.mean() - cli.mean()) < 0.01 * cli.mean()
    assert difference < 0.05
