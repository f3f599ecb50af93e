"""UsdLux lights to gi LightDesc."""
import numpy as np
from pxr import Sdf, UsdLux

from . import _core

LIGHT_KINDS = {"RectLight": "rect", "DiskLight": "disk", "SphereLight": "sphere",
               "CylinderLight": "cylinder", "DistantLight": "distant", "DomeLight": "dome",
               "DomeLight_1": "dome"}


def _get(prim, name, default):
    attr = prim.GetAttribute("inputs:" + name)
    if not attr or not attr.HasValue():
        attr = prim.GetAttribute(name)  # pre-connectable-schema files
    v = attr.Get() if attr and attr.HasValue() else None
    return default if v is None else v


def light_desc(prim, world_matrix, warn):
    kind = LIGHT_KINDS.get(prim.GetTypeName())
    if kind is None:
        return None
    d = _core.LightDesc()
    d.name = str(prim.GetPath())
    d.kind = kind
    d.color = tuple(float(c) for c in _get(prim, "color", (1, 1, 1)))
    d.intensity = float(_get(prim, "intensity", 1.0))
    d.exposure = float(_get(prim, "exposure", 0.0))
    d.normalize = bool(_get(prim, "normalize", False))
    d.width = float(_get(prim, "width", 1.0))
    d.height = float(_get(prim, "height", 1.0))
    d.radius = float(_get(prim, "radius", 0.5))
    d.length = float(_get(prim, "length", 1.0))
    d.angle = float(_get(prim, "angle", 0.53))
    texture = _get(prim, "texture:file", None)
    if isinstance(texture, Sdf.AssetPath) and texture.path:
        if texture.resolvedPath:
            d.texture_file = texture.resolvedPath
        else:
            warn(f"light {d.name}: texture {texture.path} does not resolve to a file; using its color")
    if kind == "rect" and d.texture_file:
        warn(f"light {d.name}: rect light textures are not supported; using its color")
        d.texture_file = ""
    if prim.HasAPI(UsdLux.ShapingAPI) if hasattr(UsdLux, "ShapingAPI") else False:
        warn(f"light {d.name}: shaping (cone, focus, IES) is not supported; emitting unshaped")
    camera_visibility = prim.GetAttribute("visibleInPrimaryRay")
    if camera_visibility and camera_visibility.HasValue():
        d.visible_to_camera = bool(camera_visibility.Get())
    d.transform = np.array(world_matrix, dtype=np.float64)
    return d
