"""UsdShade materials (UsdPreviewSurface networks) to gi MaterialDesc."""
import os

from pxr import Sdf, UsdShade

from . import _core

# UsdPreviewSurface input -> (MaterialDesc attribute, texture attribute or None, kind)
_INPUTS = {
    "diffuseColor": ("diffuse_color", "diffuse_color_texture", "color"),
    "emissiveColor": ("emissive_color", "emissive_color_texture", "color"),
    "specularColor": ("specular_color", "specular_color_texture", "color"),
    "metallic": ("metallic", "metallic_texture", "float"),
    "roughness": ("roughness", "roughness_texture", "float"),
    "opacity": ("opacity", "opacity_texture", "float"),
    "normal": (None, "normal_texture", "normal"),
    "clearcoat": ("clearcoat", None, "float"),
    "clearcoatRoughness": ("clearcoat_roughness", None, "float"),
    "opacityThreshold": ("opacity_threshold", None, "float"),
    "ior": ("ior", None, "float"),
    "useSpecularWorkflow": ("use_specular_workflow", None, "bool"),
}


def _value(shader, name, default=None):
    inp = shader.GetInput(name)
    if not inp:
        return default
    v = inp.Get()
    return default if v is None else v


def _connected_shader(inp):
    """(shader, output name) that an input is connected to, or (None, None)."""
    if not inp or not inp.HasConnectedSource():
        return None, None
    source, output, _ = inp.GetConnectedSource()
    return UsdShade.Shader(source.GetPrim()), output


def _texture_desc(texture, output, material_path, warn):
    desc = _core.TextureDesc()
    file_input = texture.GetInput("file")
    asset = file_input.Get() if file_input else None
    path = ""
    if isinstance(asset, Sdf.AssetPath):
        path = asset.resolvedPath or ""
        if not path and asset.path:
            warn(f"material {material_path}: texture {asset.path} of {texture.GetPath()} does not "
                 f"resolve to a file; using the constant value")
            return None
    if not path:
        return None
    if not os.path.isfile(path):
        warn(f"material {material_path}: texture file {path} does not exist; using the constant value")
        return None
    desc.file = path
    desc.wrap_s = str(_value(texture, "wrapS", "useMetadata"))
    desc.wrap_t = str(_value(texture, "wrapT", "useMetadata"))
    desc.scale = tuple(_value(texture, "scale", (1, 1, 1, 1)))
    desc.bias = tuple(_value(texture, "bias", (0, 0, 0, 0)))
    desc.fallback = tuple(_value(texture, "fallback", (0, 0, 0, 1)))
    desc.source_color_space = str(_value(texture, "sourceColorSpace", "auto"))
    desc.channel = output if output in ("r", "g", "b", "a") else "rgb"
    st_shader, _ = _connected_shader(texture.GetInput("st"))
    if st_shader and st_shader.GetIdAttr().Get() == "UsdTransform2d":
        desc.st_rotation = float(_value(st_shader, "rotation", 0.0))
        desc.st_scale = tuple(_value(st_shader, "scale", (1, 1)))
        desc.st_translation = tuple(_value(st_shader, "translation", (0, 0)))
    return desc


def surface_shader(material):
    output = material.GetSurfaceOutput()
    if not output:
        return None
    source = output.GetConnectedSource()
    if not source or not source[0]:
        return None
    return UsdShade.Shader(source[0].GetPrim())


def material_desc(material: UsdShade.Material, warn):
    """A MaterialDesc for a bound material, or None if it has no UsdPreviewSurface."""
    path = str(material.GetPath())
    shader = surface_shader(material)
    if shader is None or shader.GetIdAttr().Get() != "UsdPreviewSurface":
        warn(f"material {path}: no UsdPreviewSurface on its surface output; using the default")
        return None
    desc = _core.MaterialDesc()
    desc.name = path
    for name, (attr, texture_attr, kind) in _INPUTS.items():
        inp = shader.GetInput(name)
        if not inp:
            continue
        source, output = _connected_shader(inp)
        if source is not None and texture_attr and source.GetIdAttr().Get() == "UsdUVTexture":
            tex = _texture_desc(source, output, path, warn)
            if tex is not None:
                setattr(desc, texture_attr, tex)
            if attr:  # the texture's fallback doubles as the constant when the file is missing
                fallback = _value(source, "fallback", None)
                if fallback is not None and tex is None:
                    value = tuple(fallback)[:3] if kind == "color" else float(tuple(fallback)[0])
                    setattr(desc, attr, value)
            continue
        value = inp.Get()
        if value is None or attr is None:
            continue
        if kind == "color":
            setattr(desc, attr, tuple(float(x) for x in value))
        elif kind == "bool":
            setattr(desc, attr, bool(value))
        else:
            setattr(desc, attr, float(value))
    desc.opacity_mode = str(_value(shader, "opacityMode", "transparent"))
    return desc
