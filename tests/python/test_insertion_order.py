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

# Two lamps inside the room besides the sun and sky: emissive quads under the ceiling, unequal
# so that which is which matters, as two meshes or as two instances of one prototype (the
# loader's instances, named by their prims, in stage order). The open variant deactivates the
# pane, so that the path tracer's shadow rays reach sun and sky (behind glass they are blocked
# whichever light is picked).
LOOK = """
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
"""
QUAD = """
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-0.25, 0, -0.25), (0.25, 0, -0.25), (0.25, 0, 0.25), (-0.25, 0, 0.25)]
        rel material:binding = </World/LampLook>
"""
PLACES = {"LampA": "(-1.25, 2.95, -3.25)", "LampB": "(1, 2.95, -2)"}
SCALES = {"LampA": "(1, 1, 1)", "LampB": "(2, 1, 2)"}


def lamp(name, instanced):
    place = (f"double3 xformOp:translate = {PLACES[name]}\n        float3 xformOp:scale = {SCALES[name]}\n"
             '        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"]')
    if instanced:
        return f"""    def Xform "{name}" (instanceable = true
        references = </LampPrototype>)
    {{
        {place}
    }}
"""
    return f"""    def Mesh "{name}" (prepend apiSchemas = ["MaterialBindingAPI"])
    {{{QUAD}        {place}
    }}
"""


def stage(tmp_path, name, children, open_window, instanced):
    """The room with the lamps, World's children in the given order (`reorder nameChildren`)."""
    pane = '    over "Pane" (active = false)\n    {\n    }\n' if open_window else ""
    order = ", ".join(f'"{child}"' for child in children)
    prototype = f"""class Xform "LampPrototype"
{{
    def Mesh "Quad" (prepend apiSchemas = ["MaterialBindingAPI"])
    {{{QUAD}    }}
}}
""" if instanced else ""
    path = tmp_path / f"{name}.usda"
    path.write_text(f"""#usda 1.0
(
    subLayers = [@{ROOM}@]
)
over "World"
{{
    reorder nameChildren = [{order}]
{LOOK}{lamp("LampA", instanced)}{lamp("LampB", instanced)}{pane}}}
{prototype}""")
    return path


def render(path, integrator):
    loaded = load_stage(str(path))
    s = _core.RenderSettings()
    s.width, s.height = 48, 36
    s.spp, s.integrator, s.seed = 4, integrator, 3
    result = _core.render(loaded.scene, s)
    stats = loaded.scene.stats()
    return np.asarray(result.color), stats["lights"], stats


@pytest.mark.parametrize("integrator, open_window, instanced", [
    ("path", True, False), ("photonMapIrradianceCache", False, False), ("progressivePhotonMap", False, False),
    ("photonMapIrradianceCache", False, True)])
def test_the_order_of_lights_and_shapes_in_the_stage_changes_nothing(tmp_path, integrator, open_window, instanced):
    # File order: Sun before Sky and LampB before LampA; the reverse of each by name.
    forward = ["Sun", "Sky", "LampB", "LampA", "Floor", "Walls", "Pane"]
    a, lights_a, stats_a = render(stage(tmp_path, "forward", forward, open_window, instanced), integrator)
    b, lights_b, _ = render(stage(tmp_path, "backward", forward[::-1], open_window, instanced), integrator)
    assert lights_a == lights_b == 2 + 4  # sun, sky and the lamps' two triangles each
    assert stats_a["instances"] == (2 if instanced else 0)
    assert a.mean() > 0 and np.isfinite(a).all()
    identical = (np.abs(a - b).max(axis=-1) == 0).mean()
    print(f"{integrator}: {100 * identical:.2f}% of pixels identical, mean {a.mean():.5f} / {b.mean():.5f}")
    assert np.array_equal(a, b)
