"""UsdShade materials (UsdPreviewSurface networks) to MaterialDesc, each added to the scene once.

`warn(prim_path, message)` reports a problem; the caller adds the file name."""
import os

from pxr import Sdf, Tf, UsdGeom, UsdShade

from . import descriptors

# What reading a malformed prim can raise through the pxr API: a Tf error (an invalid xformOp, ...)
# or a value of the wrong type or shape. The loader turns these into warnings naming the prim.
UNREADABLE = (Tf.ErrorException, TypeError, ValueError, ArithmeticError, IndexError, AttributeError)


def error_text(error):
    """The last line of an exception's message (a Tf error's carries the C++ location first)."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    return lines[-1] if lines else type(error).__name__

# -- shading networks ----------------------------------------------------------------------------
# The loader only describes a material's network as the stage authors it (gi._core.ShaderNetwork,
# renderer/shader_network.h); which nodes and inputs mean what, their defaults and the warnings are
# renderer/preview_surface.h's, the rules hdGi resolves Hydra's networks by.

def asset_of(asset, attribute=None):
    """An asset-valued input as gi._core.ShaderAsset: as authored, and the file it resolves to
    ('' when no file is there). A UDIM pattern (tex.<UDIM>.exr), which no resolver resolves, is
    resolved as UsdImaging resolves it for Hydra: anchored to the layer that authors it, the
    pattern kept, when one of its tiles is there (UsdShade.UdimUtils)."""
    from ._core import ShaderAsset
    if attribute is not None and UsdShade.UdimUtils.IsUdimIdentifier(asset.path):
        layer = next((spec.layer for spec in attribute.GetPropertyStack() if spec.HasDefaultValue()), None)
        return ShaderAsset(asset.path, UsdShade.UdimUtils.ResolveUdimPath(asset.path, layer) if layer else "")
    resolved = asset.resolvedPath
    return ShaderAsset(asset.path, resolved if resolved and os.path.isfile(resolved) else "")


def constant_of(value, attribute=None):
    """An authored value as gi._core.ShaderNode.set takes it (numbers, 2 to 4 numbers, str, an
    asset); None for a value of another type (the input then reads as unauthored, as in hdGi)."""
    if isinstance(value, Sdf.AssetPath):
        return asset_of(value, attribute)
    if isinstance(value, (bool, int, float, str)):
        return value
    if hasattr(value, "__len__") and 2 <= len(value) <= 4 and all(isinstance(v, (int, float)) for v in value):
        return tuple(float(v) for v in value)
    return None


def shader_network(material):
    """(gi._core.ShaderNetwork of the shaders feeding the material's universal surface output, the
    path of the shader driving it or ''). Inputs are followed through node graphs and material
    interface inputs to the shader output or the value that produces them, as UsdImaging flattens
    them for Hydra."""
    from ._core import ShaderNetwork, ShaderNode
    network = ShaderNetwork()
    surface, _, _ = material.ComputeSurfaceSource()
    if not surface:
        return network, ""
    pending = [surface]
    while pending:
        shader = pending.pop()
        path = str(shader.GetPath())
        if path in network:
            continue
        node = ShaderNode(shader.GetShaderId() or "")
        for shader_input in shader.GetInputs():
            attributes = shader_input.GetValueProducingAttributes(shaderOutputsOnly=False)
            if not attributes:
                continue
            name, attribute = shader_input.GetBaseName(), attributes[0]
            if UsdShade.Output.IsOutput(attribute):
                upstream = UsdShade.Shader(attribute.GetPrim())
                node.connect(name, str(upstream.GetPath()), UsdShade.Output(attribute).GetBaseName())
                pending.append(upstream)
            elif (value := constant_of(attribute.Get(), attribute)) is not None:
                node.set(name, value)
        network.add(path, node)
    return network, str(surface.GetPath())


def material_desc(material, warn, textures):
    """(MaterialDesc, uv primvar names its textures read) for a bound material, or (None, ()) if no
    UsdPreviewSurface drives its surface (after a warning). Records each texture file it names in
    `textures` (as authored -> resolved file, None when missing). Without the compiled core the
    network cannot be resolved: a stand-in with the defaults is counted instead."""
    if not descriptors.HAVE_CORE:
        return descriptors.MaterialDesc(), ()
    from ._core import resolve_preview_surface
    path = str(material.GetPath())
    network, surface = shader_network(material)
    resolved = resolve_preview_surface(path, network, surface, warn)
    if resolved is None:
        return None, ()
    desc, uv_names, files = resolved
    textures.update({authored: file or None for authored, file in files})
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
