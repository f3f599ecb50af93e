"""`gi import`: Wavefront OBJ/MTL and glTF 2.0 sources to a USD layer.

The files are parsed in C++ (gi._core.read_obj with tinyobjloader, gi._core.read_gltf with
tinygltf); this module authors the USD with pxr:

- one Mesh per OBJ (group, material) pair, or per glTF primitive under the glTF node tree; faces as
  in the source (no triangulation), subdivisionScheme "none", indexed faceVarying normals and st
  (OBJ) or vertex ones (glTF); normals that are missing, zero-length or NaN are replaced by the
  geometric normal (with a warning), so none of those is ever written;
- UsdPreviewSurface materials: MTL in the specular workflow (Kd, Ks, Ns -> roughness, d / Tf ->
  opacity in "transparent" mode with Ni as ior, map_Kd, map_Ks, map_d, map_Ke, norm; a bump height
  map is kept as an unconnected UsdUVTexture, since UsdPreviewSurface has no height input), glTF in
  the metallic workflow (base colour, metallic-roughness, normal, emissive textures);
- texture files are referenced where they are (relative to the output file, or absolute with
  absolute_paths), never copied; a glTF's embedded images are written next to the output;
- upAxis / metersPerUnit, and the credits from the SOURCE.md above the source file in the layer's
  doc and customLayerData.

Output is a pure function of the inputs: importing again gives the same bytes."""
import math
import os
import re
import sys
import urllib.parse
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

DEFAULT_ASSETS = Path("..") / "shared" / "assets"
WRAP_MODES = {10497: "repeat", 33071: "clamp", 33648: "mirror"}
TRANSPARENT_ILLUM = (4, 6, 7, 9)  # MTL illumination models with refraction / transparency


class ImportError_(RuntimeError):
    """A source file cannot be imported; the message names the file."""


@dataclass
class ImportReport:
    source: str
    output: str
    meshes: int = 0
    faces: int = 0
    triangles: int = 0
    materials: int = 0
    textures: list = field(default_factory=list)   # resolved texture files
    warnings: list = field(default_factory=list)


def assets_root(explicit=None):
    """The asset folder: `explicit`, else $GI_ASSETS, else ../shared/assets (from the current
    directory, as the scripts run from the repository root)."""
    return Path(explicit or os.environ.get("GI_ASSETS") or DEFAULT_ASSETS)


def resolve_source(source, assets=None):
    """`source` as given if it exists, else relative to the asset folder."""
    path = Path(source)
    if path.exists() or path.is_absolute():
        return path
    candidate = assets_root(assets) / path
    return candidate if candidate.exists() else path


# -- names, credits ------------------------------------------------------------------------------

def identifier(name, fallback="_"):
    from pxr import Tf
    name = re.sub(r"[^A-Za-z0-9_]", "_", name or "")
    return Tf.MakeValidIdentifier(name) if name else fallback


class Names:
    """Unique prim names among siblings, in the order asked (deterministic)."""

    def __init__(self):
        self.used = set()

    def __call__(self, name):
        base, n = name, 1
        while name in self.used:
            name = f"{base}_{n}"
            n += 1
        self.used.add(name)
        return name


def source_md(source):
    """The SOURCE.md in the source's folder or the nearest one above it (None if none)."""
    for folder in [source.parent, *source.parent.parents][:4]:
        if (folder / "SOURCE.md").is_file():
            return folder / "SOURCE.md"
    return None


def credits(source):
    """(title, credit text) from the SOURCE.md above `source`: its first heading and its
    'Credit / license' section; ('', '') when there is none."""
    md = source_md(source)
    if md is None:
        return "", ""
    text = md.read_text(encoding="utf-8", errors="replace")
    title = next((line.lstrip("# ").strip() for line in text.splitlines() if line.startswith("# ")), "")
    title = re.split(r"\s+[—-]+\s+source\b", title, flags=re.I)[0]  # "Sponza — source and provenance"
    match = re.search(r"^## Credit[^\n]*\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    return title, (match.group(1).strip() if match else "")


# -- authoring helpers ---------------------------------------------------------------------------

def vt_array(vt_type, values):
    return vt_type.FromNumpy(np.ascontiguousarray(values))


class Authoring:
    """State shared by the OBJ and glTF paths: the stage, the output folder, path style, warnings."""

    def __init__(self, stage, output, source, absolute_paths, report):
        self.stage, self.output, self.source = stage, Path(output), Path(source)
        self.absolute_paths, self.report = absolute_paths, report

    def warn(self, message):
        self.report.warnings.append(f"{self.source}: {message}")

    def asset_path(self, file):
        """How the layer names a texture file: relative to the output file's folder, or absolute."""
        file = Path(os.path.abspath(file))
        if self.absolute_paths:
            return file.as_posix()
        return Path(os.path.relpath(file, os.path.abspath(self.output.parent))).as_posix()

    def texture(self, material, name, file, color_space, wrap=("repeat", "repeat"), scale=None, bias=None,
                st_scale=None, st_offset=None):
        """A UsdUVTexture reading `file` through the material's st reader (and a UsdTransform2d when
        the source scales or offsets the uvs)."""
        from pxr import Sdf, UsdShade
        self.report.textures.append(os.path.abspath(file))
        shader = UsdShade.Shader.Define(self.stage, material.GetPath().AppendChild(name))
        shader.CreateIdAttr("UsdUVTexture")
        shader.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(Sdf.AssetPath(self.asset_path(file)))
        shader.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set(color_space)
        shader.CreateInput("wrapS", Sdf.ValueTypeNames.Token).Set(wrap[0])
        shader.CreateInput("wrapT", Sdf.ValueTypeNames.Token).Set(wrap[1])
        if scale is not None:
            shader.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(tuple(scale))
        if bias is not None:
            shader.CreateInput("bias", Sdf.ValueTypeNames.Float4).Set(tuple(bias))
        reader = material.GetPrim().GetChild("stReader")
        st = UsdShade.Shader(reader).ConnectableAPI() if reader else None
        if st is None:
            reader = UsdShade.Shader.Define(self.stage, material.GetPath().AppendChild("stReader"))
            reader.CreateIdAttr("UsdPrimvarReader_float2")
            reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set("st")
            reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
            st = reader.ConnectableAPI()
        st_source = (st, "result")
        moved = (st_scale is not None and tuple(st_scale) != (1.0, 1.0)) or \
                (st_offset is not None and tuple(st_offset) != (0.0, 0.0))
        if moved:
            transform = UsdShade.Shader.Define(self.stage, material.GetPath().AppendChild(name + "Transform"))
            transform.CreateIdAttr("UsdTransform2d")
            transform.CreateInput("in", Sdf.ValueTypeNames.Float2).ConnectToSource(*st_source)
            transform.CreateInput("scale", Sdf.ValueTypeNames.Float2).Set(tuple(st_scale or (1.0, 1.0)))
            transform.CreateInput("translation", Sdf.ValueTypeNames.Float2).Set(tuple(st_offset or (0.0, 0.0)))
            transform.CreateOutput("result", Sdf.ValueTypeNames.Float2)
            st_source = (transform.ConnectableAPI(), "result")
        shader.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(*st_source)
        return shader

    def material(self, parent, name):
        """A Material with a UsdPreviewSurface driving its surface; returns (material, surface shader)."""
        from pxr import Sdf, UsdShade
        material = UsdShade.Material.Define(self.stage, parent.AppendChild(name))
        surface = UsdShade.Shader.Define(self.stage, material.GetPath().AppendChild("PreviewSurface"))
        surface.CreateIdAttr("UsdPreviewSurface")
        material.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")
        surface.CreateOutput("surface", Sdf.ValueTypeNames.Token)
        return material, surface

    def mesh(self, path, points, counts, indices, normals, normal_indices, normal_interp, uvs, uv_indices,
             uv_interp, double_sided=True):
        from pxr import Gf, Sdf, UsdGeom, Vt
        mesh = UsdGeom.Mesh.Define(self.stage, path)
        mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        mesh.CreatePointsAttr(vt_array(Vt.Vec3fArray, points))
        mesh.CreateFaceVertexCountsAttr(vt_array(Vt.IntArray, counts.astype(np.int32)))
        mesh.CreateFaceVertexIndicesAttr(vt_array(Vt.IntArray, indices.astype(np.int32)))
        mesh.CreateDoubleSidedAttr(bool(double_sided))
        if len(points):
            low, high = points.min(axis=0), points.max(axis=0)
            mesh.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, low)), Gf.Vec3f(*map(float, high))]))
        api = UsdGeom.PrimvarsAPI(mesh)
        if normals is not None and len(normals):
            primvar = api.CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, normal_interp)
            primvar.Set(vt_array(Vt.Vec3fArray, normals))
            if normal_indices is not None:
                primvar.SetIndices(vt_array(Vt.IntArray, normal_indices.astype(np.int32)))
        if uvs is not None and len(uvs):
            primvar = api.CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, uv_interp)
            primvar.Set(vt_array(Vt.Vec2fArray, uvs))
            if uv_indices is not None:
                primvar.SetIndices(vt_array(Vt.IntArray, uv_indices.astype(np.int32)))
        return mesh


def bind(mesh, material):
    from pxr import UsdShade
    UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(material)


def mtl_roughness(ns):
    """Phong exponent -> UsdPreviewSurface roughness: the Beckmann/GGX alpha with the same lobe
    width is sqrt(2 / (Ns + 2)), and roughness is sqrt(alpha)."""
    return float(min(1.0, (2.0 / (max(ns, 0.0) + 2.0)) ** 0.25))


# -- OBJ -----------------------------------------------------------------------------------------

def obj_material(auth, parent, name, m, folder):
    """An MTL material as a UsdPreviewSurface (specular workflow)."""
    from pxr import Sdf
    material, surface = auth.material(parent, name)
    kd = tuple(float(c) for c in m["Kd"])
    ks = tuple(float(c) for c in m["Ks"])
    ke = tuple(float(c) for c in m["Ke"])
    inputs = {}
    maps = m["maps"]

    def texture_file(key):
        entry = maps.get(key)
        if entry is None:
            return None
        file = folder / entry["file"].replace("\\", "/")
        if not file.is_file():
            auth.warn(f"material '{m['name']}': {key} texture '{entry['file']}' not found (looked for {file}); "
                      f"using the constant value")
            return None
        return entry, file

    def st(entry):
        return dict(st_scale=entry["scale"], st_offset=entry["offset"])

    surface.CreateInput("useSpecularWorkflow", Sdf.ValueTypeNames.Int).Set(1)
    found = texture_file("map_Kd")
    if found:
        entry, file = found
        # MTL multiplies map_Kd by Kd.
        tex = auth.texture(material, "diffuseTexture", file, "sRGB", scale=(*kd, 1.0), **st(entry))
        tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
        surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(tex.ConnectableAPI(), "rgb")
    else:
        inputs["diffuseColor"] = (Sdf.ValueTypeNames.Color3f, kd)
    found = texture_file("map_Ks")
    if found:
        entry, file = found
        tex = auth.texture(material, "specularTexture", file, "sRGB", scale=(*ks, 1.0), **st(entry))
        tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
        surface.CreateInput("specularColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(tex.ConnectableAPI(), "rgb")
    else:
        inputs["specularColor"] = (Sdf.ValueTypeNames.Color3f, ks)
    inputs["roughness"] = (Sdf.ValueTypeNames.Float, mtl_roughness(float(m["Ns"])))
    if any(ke):
        found = texture_file("map_Ke")
        if found:
            entry, file = found
            tex = auth.texture(material, "emissiveTexture", file, "sRGB", scale=(*ke, 1.0), **st(entry))
            tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
            surface.CreateInput("emissiveColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(
                tex.ConnectableAPI(), "rgb")
        else:
            inputs["emissiveColor"] = (Sdf.ValueTypeNames.Color3f, ke)
    # Transparency: dissolve d (or Tr) below 1, or a refracting illumination model with a
    # transmission filter Tf below white: a dielectric of index Ni, tinted by the diffuse colour.
    opacity = float(m["d"])
    if opacity >= 1.0 and int(m["illum"]) in TRANSPARENT_ILLUM:
        opacity = 1.0 - max(float(c) for c in m["Tf"])
    opacity = min(max(opacity, 0.0), 1.0)
    found = texture_file("map_d")
    if found:
        entry, file = found
        tex = auth.texture(material, "opacityTexture", file, "raw", **st(entry))
        tex.CreateOutput("r", Sdf.ValueTypeNames.Float)
        surface.CreateInput("opacity", Sdf.ValueTypeNames.Float).ConnectToSource(tex.ConnectableAPI(), "r")
        inputs["opacityMode"] = (Sdf.ValueTypeNames.Token, "presence")  # a cut-out mask
    elif opacity < 1.0:
        inputs["opacity"] = (Sdf.ValueTypeNames.Float, opacity)
        inputs["opacityMode"] = (Sdf.ValueTypeNames.Token, "transparent")
    inputs["ior"] = (Sdf.ValueTypeNames.Float, float(m["Ni"]) if float(m["Ni"]) >= 1.0 else 1.5)
    for key, (kind, value) in inputs.items():
        surface.CreateInput(key, kind).Set(value)
    found = texture_file("norm")
    if found:
        entry, file = found
        tex = auth.texture(material, "normalTexture", file, "raw", scale=(2, 2, 2, 1), bias=(-1, -1, -1, 0), **st(entry))
        tex.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
        surface.CreateInput("normal", Sdf.ValueTypeNames.Normal3f).ConnectToSource(tex.ConnectableAPI(), "rgb")
    found = texture_file("bump")
    if found:
        entry, file = found
        tex = auth.texture(material, "bumpTexture", file, "raw", **st(entry))
        tex.CreateOutput("r", Sdf.ValueTypeNames.Float)
        tex.GetPrim().SetDocumentation(
            f"MTL bump height map (-bm {entry['bump_multiplier']:g}). UsdPreviewSurface has no height "
            f"input, so it drives nothing; kept for renderers that read it.")
    return material


def import_obj(auth, source, root):
    from pxr import UsdGeom
    from . import _core
    try:
        data = _core.read_obj(str(source))
    except RuntimeError as error:
        raise ImportError_(str(error)) from None
    for line in filter(None, (data["warnings"] or "").splitlines()):
        if "Both `d` and `Tr`" not in line:  # 3ds Max exports always write both; d wins, as it should
            auth.warn(line.strip())
    if data["repaired_normals"]:
        auth.warn(f"{data['repaired_normals']} zero-length or NaN normals replaced by face normals")
    if data["degenerate_faces"]:
        auth.warn(f"{data['degenerate_faces']} degenerate (zero-area) faces kept as they are")
    folder = source.parent
    materials_scope = UsdGeom.Scope.Define(auth.stage, root.AppendChild("Materials")).GetPath()
    material_names = Names()
    materials = [obj_material(auth, materials_scope, material_names(identifier(m["name"], "material")), m, folder)
                 for m in data["materials"]]
    geometry = UsdGeom.Scope.Define(auth.stage, root.AppendChild("Geometry")).GetPath()
    meshes = data["meshes"]
    shape_names = [m["name"] for m in meshes]
    one_shape = len(set(shape_names)) == 1
    per_shape = {name: sum(1 for s in shape_names if s == name) for name in shape_names}
    names = Names()
    for m in meshes:
        material = materials[m["material"]] if 0 <= m["material"] < len(materials) else None
        material_name = data["materials"][m["material"]]["name"] if material else "default"
        if one_shape and per_shape[m["name"]] > 1 or not m["name"]:
            name = material_name if material else source.stem
        elif per_shape[m["name"]] > 1:
            name = f"{m['name']}_{material_name}"
        else:
            name = m["name"]
        counts = m["face_vertex_counts"]
        uvs = m["uvs"] if len(m["uv_indices"]) else None
        mesh = auth.mesh(geometry.AppendChild(names(identifier(name, "mesh"))), m["points"], counts,
                         m["face_vertex_indices"], m["normals"], m["normal_indices"], UsdGeom.Tokens.faceVarying,
                         uvs, m["uv_indices"] if uvs is not None else None, UsdGeom.Tokens.faceVarying)
        if material is not None:
            bind(mesh, material)
        elif materials:  # the OBJ has a material library, but not this mesh's material
            auth.warn(f"mesh '{mesh.GetPath().name}' has no material of the .mtl (its usemtl names one the "
                      f"library lacks): it renders with the default grey material, and emits no light")
        auth.report.meshes += 1
        auth.report.faces += len(counts)
        auth.report.triangles += int(np.sum(np.maximum(counts - 2, 0)))
    auth.report.materials = len(materials)
    return {"groups": len(set(shape_names)), "materials": len(materials)}


# -- glTF ----------------------------------------------------------------------------------------

IMAGE_EXTENSIONS = {"image/png": ".png", "image/jpeg": ".jpg", "image/webp": ".webp"}


def gltf_image_files(auth, data, source):
    """Image index -> file: an external image where it is, an embedded one written next to the
    output (`<output stem>_textures/`)."""
    files = []
    for i, image in enumerate(data["images"]):
        if image["uri"]:
            file = source.parent / urllib.parse.unquote(image["uri"])
            if not file.is_file():
                auth.warn(f"image {i} '{image['uri']}' not found (looked for {file}); using constant values")
                file = None
        elif image["bytes"]:
            folder = auth.output.parent / f"{auth.output.stem}_textures"
            folder.mkdir(parents=True, exist_ok=True)
            name = identifier(image["name"], f"image{i}") if image["name"] else f"image{i}"
            file = folder / f"{i:03d}_{name}{IMAGE_EXTENSIONS.get(image['mime_type'], '.png')}"
            if not file.is_file() or file.read_bytes() != image["bytes"]:
                file.write_bytes(image["bytes"])
        else:
            auth.warn(f"image {i} has no data; using constant values")
            file = None
        files.append(file)
    return files


def gltf_material(auth, parent, name, m, images):
    from pxr import Sdf
    material, surface = auth.material(parent, name)
    base = list(m["base_color"]) + [1.0] * (4 - len(m["base_color"]))

    def texture(key, node, color_space, output, output_type, scale=None, bias=None):
        ref = m[key]
        if not ref:
            return None
        if ref["texcoord"] != 0:
            auth.warn(f"material '{m['name']}': {key} uses TEXCOORD_{ref['texcoord']}; only TEXCOORD_0 is imported")
        image = ref["image"]
        file = images[image] if 0 <= image < len(images) else None
        if file is None:
            return None
        wrap = (WRAP_MODES.get(ref["wrap_s"], "repeat"), WRAP_MODES.get(ref["wrap_t"], "repeat"))
        tex = auth.texture(material, node, file, color_space, wrap, scale=scale, bias=bias)
        tex.CreateOutput(output, output_type)
        return tex.ConnectableAPI(), output

    surface.CreateInput("useSpecularWorkflow", Sdf.ValueTypeNames.Int).Set(0)
    connected = texture("base_color_texture", "baseColorTexture", "sRGB", "rgb", Sdf.ValueTypeNames.Float3,
                        scale=base)
    diffuse = surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f)
    diffuse.ConnectToSource(*connected) if connected else diffuse.Set(tuple(base[:3]))
    metal_rough = m["metallic_roughness_texture"]
    for key, channel, factor in (("metallic", "b", m["metallic"]), ("roughness", "g", m["roughness"])):
        attr = surface.CreateInput(key, Sdf.ValueTypeNames.Float)
        connected = metal_rough and texture("metallic_roughness_texture", "metallicRoughnessTexture", "raw", channel,
                                            Sdf.ValueTypeNames.Float, scale=(factor,) * 4)
        attr.ConnectToSource(*connected) if connected else attr.Set(float(factor))
    emissive = tuple(float(c) for c in m["emissive"]) or (0.0, 0.0, 0.0)
    if any(emissive):
        attr = surface.CreateInput("emissiveColor", Sdf.ValueTypeNames.Color3f)
        connected = texture("emissive_texture", "emissiveTexture", "sRGB", "rgb", Sdf.ValueTypeNames.Float3,
                            scale=(*emissive, 1.0))
        attr.ConnectToSource(*connected) if connected else attr.Set(emissive)
    scale = float(m["normal_scale"])
    connected = texture("normal_texture", "normalTexture", "raw", "rgb", Sdf.ValueTypeNames.Float3,
                        scale=(2 * scale, 2 * scale, 2, 1), bias=(-scale, -scale, -1, 0))
    if connected:
        surface.CreateInput("normal", Sdf.ValueTypeNames.Normal3f).ConnectToSource(*connected)
    ior = float(m.get("ior", 1.5))
    surface.CreateInput("ior", Sdf.ValueTypeNames.Float).Set(ior)
    if "transmission" in m and m["transmission"] > 0:
        surface.CreateInput("opacity", Sdf.ValueTypeNames.Float).Set(float(1.0 - m["transmission"]))
        surface.CreateInput("opacityMode", Sdf.ValueTypeNames.Token).Set("transparent")
    elif m["alpha_mode"] in ("BLEND", "MASK"):
        # glTF alpha is coverage, not refraction: UsdPreviewSurface's "presence" cut-out.
        surface.CreateInput("opacity", Sdf.ValueTypeNames.Float).Set(float(base[3]))
        surface.CreateInput("opacityMode", Sdf.ValueTypeNames.Token).Set("presence")
        if m["alpha_mode"] == "MASK":
            surface.CreateInput("opacityThreshold", Sdf.ValueTypeNames.Float).Set(float(m["alpha_cutoff"]))
    if m["occlusion_texture"]:
        auth.warn(f"material '{m['name']}': occlusionTexture has no UsdPreviewSurface input; left out")
    return material


def node_matrix(node):
    """A glTF node's local transform as a Gf.Matrix4d (row vectors, as USD's)."""
    from pxr import Gf
    if len(node["matrix"]) == 16:
        return Gf.Matrix4d(*node["matrix"])  # column-major column-vector == row-major row-vector
    t = node["translation"] or [0.0, 0.0, 0.0]
    r = node["rotation"] or [0.0, 0.0, 0.0, 1.0]
    s = node["scale"] or [1.0, 1.0, 1.0]
    scale = Gf.Matrix4d().SetScale(Gf.Vec3d(*s))
    rotation = Gf.Matrix4d().SetRotate(Gf.Quatd(r[3], Gf.Vec3d(r[0], r[1], r[2])))
    translation = Gf.Matrix4d().SetTranslate(Gf.Vec3d(*t))
    return scale * rotation * translation


def import_gltf(auth, source, root):
    from pxr import UsdGeom
    from . import _core
    try:
        data = _core.read_gltf(str(source))
    except RuntimeError as error:
        raise ImportError_(str(error)) from None
    for line in filter(None, (data["warnings"] or "").splitlines()):
        auth.warn(line.strip())
    if data["repaired_normals"]:
        auth.warn(f"{data['repaired_normals']} zero-length or NaN normals replaced by vertex normals of the faces")
    images = gltf_image_files(auth, data, source)
    materials_scope = UsdGeom.Scope.Define(auth.stage, root.AppendChild("Materials")).GetPath()
    material_names = Names()
    materials = [gltf_material(auth, materials_scope, material_names(identifier(m["name"], f"material{i}")), m, images)
                 for i, m in enumerate(data["materials"])]
    double_sided = [bool(m["double_sided"]) for m in data["materials"]]
    nodes = data["nodes"]
    visiting = set()

    def add_node(index, parent, names):
        if not 0 <= index < len(nodes) or index in visiting:
            auth.warn(f"node {index} does not exist or is its own ancestor; skipped")
            return
        visiting.add(index)
        node = nodes[index]
        xform = UsdGeom.Xform.Define(auth.stage, parent.AppendChild(names(identifier(node["name"], f"node{index}"))))
        xform.AddTransformOp().Set(node_matrix(node))
        children = Names()
        mesh_index = node["mesh"]
        if 0 <= mesh_index < len(data["meshes"]):
            mesh = data["meshes"][mesh_index]
            primitives = [p for p in mesh["primitives"] if p]
            if len(primitives) < len(mesh["primitives"]):
                auth.warn(f"mesh {mesh_index}: point and line primitives left out")
            base = identifier(mesh["name"], f"mesh{mesh_index}")
            for k, p in enumerate(primitives):
                name = children(base if len(primitives) == 1 else f"{base}_{k}")
                indices = p["face_vertex_indices"]
                counts = np.full(len(indices) // 3, 3, np.int32)
                material = materials[p["material"]] if 0 <= p["material"] < len(materials) else None
                sided = double_sided[p["material"]] if material is not None else False
                usd_mesh = auth.mesh(xform.GetPath().AppendChild(name), p["points"], counts, indices, p["normals"],
                                     None, UsdGeom.Tokens.vertex, p["uvs"] if len(p["uvs"]) else None, None,
                                     UsdGeom.Tokens.vertex, double_sided=sided)
                if material is not None:
                    bind(usd_mesh, material)
                auth.report.meshes += 1
                auth.report.faces += len(counts)
                auth.report.triangles += len(counts)
        for child in node["children"]:
            add_node(child, xform.GetPath(), children)
        visiting.discard(index)

    names = Names()
    names("Materials")
    for index in data["roots"]:
        add_node(index, root, names)
    auth.report.materials = len(materials)
    return {"groups": len(data["meshes"]), "materials": len(materials), "generator": data["generator"],
            "copyright": data["copyright"]}


# -- the command ---------------------------------------------------------------------------------

def import_file(source, output, up_axis=None, meters_per_unit=None, absolute_paths=False, assets=None,
                name=None) -> ImportReport:
    """Imports one OBJ or glTF file into a new USD layer at `output` (its format from the extension).

    up_axis: 'Y' or 'Z' (default: Y, glTF's and the usual OBJ convention).
    meters_per_unit: the source's unit (default 1: metres).
    Raises ImportError_ naming the file when it cannot be read."""
    from pxr import Sdf, Usd, UsdGeom
    source = resolve_source(source, assets)
    output = Path(output)
    if not source.is_file():
        raise ImportError_(f"{source}: no such file")
    kind = source.suffix.lower()
    if kind not in (".obj", ".gltf", ".glb"):
        raise ImportError_(f"{source}: unknown source format '{kind}' (gi import reads .obj, .gltf and .glb)")
    if output.suffix.lower() not in (".usd", ".usda", ".usdc"):
        raise ImportError_(f"{output}: the output must be a .usd, .usda or .usdc file")
    up_axis = (up_axis or "Y").upper()
    if up_axis not in ("Y", "Z"):
        raise ImportError_(f"up axis must be Y or Z, not {up_axis}")
    meters_per_unit = 1.0 if meters_per_unit is None else float(meters_per_unit)
    if not meters_per_unit > 0 or not math.isfinite(meters_per_unit):
        raise ImportError_(f"meters per unit must be a positive number, not {meters_per_unit}")
    output.parent.mkdir(parents=True, exist_ok=True)

    report = ImportReport(str(source), str(output))
    # Author in memory, then export once: the file is written in one go, and the same inputs give
    # the same bytes.
    layer = Sdf.Layer.CreateAnonymous(output.suffix)
    stage = Usd.Stage.Open(layer)
    root_name = identifier(name or source.stem, "model")
    root = UsdGeom.Xform.Define(stage, Sdf.Path.absoluteRootPath.AppendChild(root_name))
    Usd.ModelAPI(root).SetKind("component")
    stage.SetDefaultPrim(root.GetPrim())
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y if up_axis == "Y" else UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, meters_per_unit)
    auth = Authoring(stage, output, source, absolute_paths, report)
    counts = (import_obj if kind == ".obj" else import_gltf)(auth, source, root.GetPath())

    title, credit = credits(source)
    if kind != ".obj" and counts.get("copyright"):
        credit = "\n\n".join(filter(None, [credit, f"glTF asset copyright: {counts['copyright']}"]))
    layer.documentation = (f"{title or source.name}: imported from {source.name} by `gi import`."
                           + (f"\n\nCredits:\n{credit}" if credit else ""))
    data = {"source": source.name, "title": title, "credits": credit,
            "meshes": report.meshes, "faces": report.faces, "triangles": report.triangles,
            "groups": counts["groups"], "materials": counts["materials"],
            "textures": len(set(report.textures))}
    layer.customLayerData = {"gi:import": data}
    if not layer.Export(str(output)):
        raise ImportError_(f"{output}: could not be written")
    report.textures = sorted(set(report.textures))
    return report


def cmd_import(args):
    from .errors import SceneError
    import time
    start = time.perf_counter()
    try:
        report = import_file(args.source, args.output, args.up_axis, args.meters_per_unit, args.absolute_paths,
                             args.assets, args.name)
    except ImportError_ as error:
        raise SceneError(str(error)) from None
    for message in report.warnings:
        print(f"gi: warning: {message}", file=sys.stderr)
    print(f"{report.source} -> {report.output}: {report.meshes} meshes, {report.faces} faces "
          f"({report.triangles} triangles), {report.materials} materials, {len(report.textures)} textures "
          f"in {time.perf_counter() - start:.2f} s")
    return 0
