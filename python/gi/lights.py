"""UsdLux lights to LightDesc.

`warn(prim_path, message)` reports a problem; the caller adds the file name."""
import os

import numpy as np
from pxr import Sdf, UsdLux

from . import descriptors

LIGHT_KINDS = {"RectLight": "rect", "DiskLight": "disk", "SphereLight": "sphere",
               "CylinderLight": "cylinder", "DistantLight": "distant", "DomeLight": "dome",
               "DomeLight_1": "dome", "PortalLight": "portal"}

# LightDesc field -> (UsdLux input, kind). Unauthored inputs take the schema's fallback.
COMMON_INPUTS = {"color": ("color", "color"), "intensity": ("intensity", "float"),
                 "exposure": ("exposure", "float"), "normalize": ("normalize", "bool")}
SHAPE_INPUTS = {
    "rect": {"width": "width", "height": "height"},
    "disk": {"radius": "radius"},
    "sphere": {"radius": "radius"},
    "cylinder": {"radius": "radius", "length": "length"},
    "distant": {"angle": "angle"},
    "dome": {},
    "portal": {"width": "width", "height": "height"},
}


def is_light(prim):
    return prim.HasAPI(UsdLux.LightAPI)


def light_kind(prim):
    """'rect', 'disk', ... or None for light types the renderer does not have."""
    return LIGHT_KINDS.get(prim.GetTypeName())


def light_input(prim, name, time):
    """An input's value: inputs:<name>, else the pre-UsdLux-21.05 un-prefixed <name>, else the
    schema's fallback (None if there is none)."""
    attribute = prim.GetAttribute("inputs:" + name)
    legacy = prim.GetAttribute(name)
    if not (attribute and attribute.HasAuthoredValue()) and legacy and legacy.HasAuthoredValue():
        attribute = legacy
    return attribute.Get(time) if attribute else None


def converted(value, kind):
    if kind == "color":
        return tuple(float(c) for c in value)
    if kind == "bool":
        return bool(value)
    return float(value)


def light_texture(prim, kind, time, warn):
    """Resolved path of a dome's (or rect's) inputs:texture:file, '' when none or missing."""
    if kind not in ("dome", "rect"):
        return ""
    asset = light_input(prim, "texture:file", time)
    if not isinstance(asset, Sdf.AssetPath) or not asset.path:
        return ""
    resolved = asset.resolvedPath
    if not resolved or not os.path.isfile(resolved):
        warn(str(prim.GetPath()), f"texture file '{asset.path}' was not found; using the light's color")
        return ""
    if kind == "dome":
        layout = light_input(prim, "texture:format", time)
        if layout not in (None, "automatic", "latlong"):
            warn(str(prim.GetPath()), f"texture:format '{layout}' is not supported; read as latlong")
    return resolved


def warn_unsupported_features(prim, time, warn):
    path = str(prim.GetPath())
    if prim.HasAPI(UsdLux.ShapingAPI):
        warn(path, "shaping (cone, focus, IES profile) is not supported; emitting unshaped")
    filters = UsdLux.LightAPI(prim).GetFiltersRel().GetTargets()
    if filters:
        warn(path, f"{len(filters)} light filters are not supported; ignored")
    if light_input(prim, "treatAsPoint", time) or light_input(prim, "treatAsLine", time):
        warn(path, "treatAsPoint/treatAsLine is not supported; emitting from the light's full shape")


def visible_to_camera(prim, time):
    """Area lights show in camera rays unless a visibleInPrimaryRay input says otherwise."""
    value = light_input(prim, "visibleInPrimaryRay", time)
    return True if value is None else bool(value)


def light_desc(prim, world_matrix, time, warn):
    """LightDesc of a UsdLux light prim, or None (with a warning) for unsupported light types."""
    path = str(prim.GetPath())
    kind = light_kind(prim)
    if kind is None:
        warn(path, f"{prim.GetTypeName() or 'this light'} is not supported; ignored")
        return None
    desc = descriptors.LightDesc()
    desc.name = path
    desc.kind = kind
    for field, (name, value_kind) in COMMON_INPUTS.items():
        value = light_input(prim, name, time)
        if value is not None:
            setattr(desc, field, converted(value, value_kind))
    for field, name in SHAPE_INPUTS[kind].items():
        value = light_input(prim, name, time)
        if value is not None:
            setattr(desc, field, float(value))
    desc.texture_file = light_texture(prim, kind, time, warn)
    desc.visible_to_camera = visible_to_camera(prim, time)
    desc.transform = np.array(world_matrix, dtype=np.float64)
    warn_unsupported_features(prim, time, warn)
    return desc
