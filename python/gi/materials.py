"""UsdShade materials (UsdPreviewSurface networks) to MaterialDesc, each added to the scene once.

`warn(prim_path, message)` reports a problem; the caller adds the file name."""
import os
from dataclasses import dataclass

from pxr import Sdf, Tf, UsdGeom, UsdShade

from . import descriptors

# What reading a malformed prim can raise through the pxr API: a Tf error (an invalid xformOp, ...)
# or a value of the wrong type or shape. The loader turns these into warnings naming the prim.
UNREADABLE = (Tf.ErrorException, TypeError, ValueError, ArithmeticError, IndexError, AttributeError)


def error_text(error):
    """The last line of an exception's message (a Tf error's carries the C++ location first)."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    return lines[-1] if lines else type(error).__name__

# UsdPreviewSurface input -> (MaterialDesc field, its TextureDesc field, kind). A None field means
# the renderer has no use for it (a constant there is ignored silently). An input with no value
# keeps the descriptor's default: the spec's, written once in renderer/material.h.
PREVIEW_SURFACE_INPUTS = {
    "diffuseColor": ("diffuse_color", "diffuse_color_texture", "color"),
    "emissiveColor": ("emissive_color", "emissive_color_texture", "color"),
    "useSpecularWorkflow": ("use_specular_workflow", None, "bool"),
    "specularColor": ("specular_color", "specular_color_texture", "color"),
    "metallic": ("metallic", "metallic_texture", "float"),
    "roughness": ("roughness", "roughness_texture", "float"),
    "clearcoat": ("clearcoat", None, "float"),
    "clearcoatRoughness": ("clearcoat_roughness", None, "float"),
    "opacity": ("opacity", "opacity_texture", "float"),
    "opacityMode": ("opacity_mode", None, "token"),
    "opacityThreshold": ("opacity_threshold", None, "float"),
    "ior": ("ior", None, "float"),
    "normal": (None, "normal_texture", "normal"),
}

# UsdUVTexture inputs read into TextureDesc (unauthored: its default, the spec's, renderer/texture.h).
TEXTURE_INPUTS = {"wrapS": "wrap_s", "wrapT": "wrap_t", "scale": "scale", "bias": "bias", "fallback": "fallback",
                  "sourceColorSpace": "source_color_space"}
CHANNELS = {"r": 0, "g": 1, "b": 2, "a": 3}


# -- reading shader networks ---------------------------------------------------------------------

@dataclass
class Source:
    """What drives a shader input: a constant (value, None when nothing is authored) or a shader's output."""
    value: object = None
    shader: UsdShade.Shader = None
    output: str = ""


def input_source(shader, name):
    """Follows connections (through node graphs and material interface inputs) to what drives `name`."""
    shader_input = shader.GetInput(name)
    if not shader_input:
        return Source()
    attributes = shader_input.GetValueProducingAttributes(shaderOutputsOnly=False)
    if not attributes:
        return Source()
    attribute = attributes[0]
    if UsdShade.Output.IsOutput(attribute):
        return Source(shader=UsdShade.Shader(attribute.GetPrim()),
                      output=UsdShade.Output(attribute).GetBaseName())
    return Source(value=attribute.Get())


def input_value(shader, name, default):
    value = input_source(shader, name).value
    return default if value is None else value


def shader_id(shader):
    return shader.GetShaderId() or ""


def converted(value, kind):
    if kind == "color":
        return tuple(float(c) for c in value)[:3]
    if kind == "bool":
        return bool(value)
    if kind == "token":
        return str(value)
    return float(value)


# -- textures ------------------------------------------------------------------------------------

@dataclass
class TextureRead:
    desc: object = None           # TextureDesc; its file is '' when missing (the fallback stands in)
    uv_primvar: str = ""          # UsdPrimvarReader_float2's varname


def texture_file(texture, material_path, warn, seen):
    """Resolved absolute path of a UsdUVTexture's file, or '' (with a warning naming the
    material and the file) when it cannot be found."""
    asset = input_value(texture, "file", None)
    if not isinstance(asset, Sdf.AssetPath) or not asset.path:
        warn(material_path, f"texture {texture.GetPath()} has no file; using its fallback")
        return ""
    resolved = asset.resolvedPath
    exists = bool(resolved) and os.path.isfile(resolved)
    seen[asset.path] = resolved if exists else None
    if not exists:
        warn(material_path, f"texture file '{asset.path}' (read by {texture.GetPath()}) was not found; "
                            f"using its fallback")
        return ""
    return resolved


def read_st_network(texture, desc):
    """UsdTransform2d (optional) and UsdPrimvarReader_float2 feeding a texture's st: fills the
    transform into `desc` and returns the primvar name."""
    source = input_source(texture, "st")
    if source.shader is not None and shader_id(source.shader) == "UsdTransform2d":
        transform = source.shader
        desc.st_rotation = float(input_value(transform, "rotation", desc.st_rotation))
        desc.st_scale = tuple(float(v) for v in input_value(transform, "scale", desc.st_scale))
        desc.st_translation = tuple(float(v) for v in input_value(transform, "translation", desc.st_translation))
        source = input_source(transform, "in")
    if source.shader is not None and shader_id(source.shader).startswith("UsdPrimvarReader"):
        return str(input_value(source.shader, "varname", ""))
    return ""


def read_texture(texture, output, material_path, warn, seen) -> TextureRead:
    desc = descriptors.TextureDesc()
    desc.file = texture_file(texture, material_path, warn, seen)
    for name, field in TEXTURE_INPUTS.items():
        value = input_value(texture, name, getattr(desc, field))
        setattr(desc, field, str(value) if isinstance(value, str) else tuple(float(v) for v in value))
    desc.channel = output if output in CHANNELS else "rgb"
    return TextureRead(desc, read_st_network(texture, desc))


def connect_texture(desc, name, field, texture_field, texture):
    """The texture on the input and, as the input's constant, what it reads when the file is
    missing (gi._core.texture_stand_in: renderer/usd_shading.h's rule, shared with hdGi). Without the
    compiled core nothing renders, so only the texture is set."""
    setattr(desc, texture_field, texture)
    try:
        from ._core import texture_stand_in
    except ImportError:
        return
    constant = texture_stand_in(name, tuple(texture.fallback), texture.channel)
    if field is not None and constant is not None:
        setattr(desc, field, constant)


# -- UsdPreviewSurface ---------------------------------------------------------------------------

def surface_shader(material):
    """The UsdPreviewSurface driving a material's universal surface output, or None."""
    shader, _, _ = material.ComputeSurfaceSource()
    if not shader or shader_id(shader) != "UsdPreviewSurface":
        return None
    return shader


def read_input(shader, name, spec, desc, material_path, warn, textures):
    """Sets one UsdPreviewSurface input on `desc`; returns the uv primvar its texture reads, if any."""
    field, texture_field, kind = spec
    source = input_source(shader, name)
    if source.shader is None:
        if field is not None and source.value is not None:
            setattr(desc, field, converted(source.value, kind))
        return ""
    if shader_id(source.shader) != "UsdUVTexture" or texture_field is None:
        warn(material_path, f"inputs:{name} is driven by {source.shader.GetPath()} "
                            f"({shader_id(source.shader) or 'no id'}), which is not supported there; "
                            f"using the default")
        return ""
    texture = read_texture(source.shader, source.output, material_path, warn, textures)
    connect_texture(desc, name, field, texture_field, texture.desc)
    return texture.uv_primvar


def once(warn):
    """`warn` that drops repeats (one missing file feeding several inputs is one problem)."""
    said = set()

    def warn_once(path, message):
        if (path, message) not in said:
            said.add((path, message))
            warn(path, message)
    return warn_once


def material_desc(material, warn, textures):
    """(MaterialDesc, uv primvar names its textures read) for a bound material, or (None, ())
    if it has no UsdPreviewSurface."""
    path = str(material.GetPath())
    warn = once(warn)
    shader = surface_shader(material)
    if shader is None:
        warn(path, "no UsdPreviewSurface drives its surface output; using the default material")
        return None, ()
    desc = descriptors.MaterialDesc()
    desc.name = path
    uv_names = []
    for name, spec in PREVIEW_SURFACE_INPUTS.items():
        uv_name = read_input(shader, name, spec, desc, path, warn, textures)
        if uv_name and uv_name not in uv_names:
            uv_names.append(uv_name)
    if input_source(shader, "displacement").shader is not None:
        warn(path, "displacement is not supported; ignored")
    return desc, tuple(uv_names)


def display_color_desc(prim_path, rgb):
    try:
        from ._core import display_color_material
    except ImportError:  # no compiled core (gi inspect): only counted
        return descriptors.MaterialDesc()
    return display_color_material(prim_path, rgb)


# -- binding -------------------------------------------------------------------------------------

class MaterialLibrary:
    """Finds the material bound to each gprim and adds each material to the scene once."""

    def __init__(self, scene, time, warn):
        self.scene, self.time, self.warn = scene, time, warn
        self.ids = {}           # material prim path (or displayColor) -> (id, uv primvar names)
        self.textures = {}      # texture asset path as authored -> resolved file, None if missing
        self.added = 0

    def bind(self, prim, display_color=True):
        """(material id, uv primvar names) for a gprim: its bound material, else (display_color) its
        displayColor material, else -1."""
        material, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial(UsdShade.Tokens.full)
        if material:
            key = str(material.GetPath())
            if key not in self.ids:
                try:
                    desc, uv_names = material_desc(material, self.warn, self.textures)
                except UNREADABLE as error:
                    self.warn(key, f"could not be read ({error_text(error)}); using the default material")
                    desc, uv_names = None, ()
                self.ids[key] = (self.add(desc), uv_names) if desc is not None else (-1, ())
            if self.ids[key][0] >= 0:
                return self.ids[key]
        return (self.display_color_material(prim) if display_color else -1), ()

    def display_color_material(self, prim):
        """The material of a gprim with no usable material (renderer/usd_shading.h, shared with hdGi):
        UsdPreviewSurface defaults with its displayColor (the first value; the prim's own primvar,
        else the nearest ancestor's constant one, as UsdImaging inherits primvars) as diffuse colour.
        Shared by prims of equal colour."""
        primvar = UsdGeom.PrimvarsAPI(prim).FindPrimvarWithInheritance("displayColor")
        colors = primvar.ComputeFlattened(self.time) if primvar and primvar.HasValue() else None
        rgb = tuple(float(c) for c in colors[0]) if colors is not None and len(colors) else None
        key = ("displayColor", rgb)
        if key not in self.ids:
            self.ids[key] = (self.add(display_color_desc(str(prim.GetPath()), rgb)), ())
        return self.ids[key][0]

    def add(self, desc):
        material_id = self.scene.add_material(desc)
        self.added += material_id >= 0
        return material_id
