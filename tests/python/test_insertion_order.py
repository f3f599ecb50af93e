"""Hosts add lights and shapes to the scene in their own order: the USD loader in stage order,
hdGi in Hydra's path order (issue 18: usdrecord and `gi render` differed on the glazed room under
sun and sky, whose Sun comes before Sky in the file but after it by path). The renderer puts its
lights in order of their names, so the same stage with its prims in another order renders the same
image bit for bit, whatever integrator picks lights by index (light selection in the path tracer,
photon emission with its pilot and guide). tests/hydra/test_portals.py checks the two hosts."""
import numpy as np
import pytest

from conftest import ROOT
from gi import _core
from gi.loader import load_stage

ROOM = ROOT / "scenes" / "window_room" / "window_room.usda"

# Two lamps inside the room (emissive quads under the ceiling, unequal so that which is which
# matters) besides the sun and sky; the open variant deactivates the pane, so that the path
# tracer's shadow rays reach sun and sky (behind glass they are blocked whichever light is picked).
LAMPS = """
    def Material "LampLook"
    {
        token outputs:surface.connect = </World/LampLook/Surface.outputs:surface>
        def Shader "Surface"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (0, 0, 0)
            color3f inputs:emissiveColor = (4, 3, 2)
            token outputs:surface
        }
    }
    def Mesh "LampA" (prepend apiSchemas = ["MaterialBindingAPI"])
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1.5, 2.95, -3.5), (-1, 2.95, -3.5), (-1, 2.95, -3), (-1.5, 2.95, -3)]
        rel material:binding = </World/LampLook>
    }
    def Mesh "LampB" (prepend apiSchemas = ["MaterialBindingAPI"])
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(0.5, 2.95, -2.5), (1.5, 2.95, -2.5), (1.5, 2.95, -1.5), (0.5, 2.95, -1.5)]
        rel material:binding = </World/LampLook>
    }
"""


def stage(tmp_path, name, children, open_window):
    """The room with the lamps, World's children in the given order (`reorder nameChildren`)."""
    pane = '    over "Pane" (active = false)\n    {\n    }\n' if open_window else ""
    order = ", ".join(f'"{child}"' for child in children)
    path = tmp_path / f"{name}.usda"
    path.write_text(f"""#usda 1.0
(
    subLayers = [@{ROOM}@]
)
over "World"
{{
    reorder nameChildren = [{order}]
{LAMPS}
{pane}}}
""")
    return path


def render(path, integrator):
    loaded = load_stage(str(path))
    s = _core.RenderSettings()
    s.width, s.height = 48, 36
    s.spp, s.integrator, s.seed = 4, integrator, 3
    result = _core.render(loaded.scene, s)
    return np.asarray(result.color), loaded.scene.stats()["lights"]


@pytest.mark.parametrize("integrator, open_window", [("path", True), ("photonMapIrradianceCache", False),
                                                     ("progressivePhotonMap", False)])
def test_the_order_of_lights_and_shapes_in_the_stage_changes_nothing(tmp_path, integrator, open_window):
    # File order: Sun before Sky and LampB before LampA; the reverse of each by name.
    forward = stage(tmp_path, "forward", ["Sun", "Sky", "LampB", "LampA", "Floor", "Walls", "Pane"], open_window)
    backward = stage(tmp_path, "backward", ["Pane", "Walls", "Floor", "LampA", "LampB", "Sky", "Sun"], open_window)
    a, lights_a = render(forward, integrator)
    b, lights_b = render(backward, integrator)
    assert lights_a == lights_b == 2 + 4  # sun, sky and the lamps' two triangles each
    assert a.mean() > 0 and np.isfinite(a).all()
    identical = (np.abs(a - b).max(axis=-1) == 0).mean()
    print(f"{integrator}: {100 * identical:.2f}% of pixels identical, mean {a.mean():.5f} / {b.mean():.5f}")
    assert np.array_equal(a, b)
