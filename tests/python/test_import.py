"""`gi import`: OBJ and glTF sources to USD. The source counts are computed here independently of
the importer (by reading the OBJ/MTL text); tests on the shared assets skip when they are absent."""
import base64
import json
import os
import re
import struct
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, run_gi

pytest.importorskip("gi._core", reason="gi._core (the compiled renderer) is not built")
from pxr import Sdf, Usd, UsdGeom, UsdShade  # noqa: E402

from gi.importer import ImportError_, import_file  # noqa: E402

ASSETS = Path(os.environ.get("GI_ASSETS") or ROOT.parent / "shared" / "assets")
SIBENIK = ASSETS / "sibenik" / "sibenik.obj"
STAKLO = ASSETS / "sibenik" / "extras" / "staklo.obj"
SPONZA = ASSETS / "sponza" / "dabrovic" / "sponza.obj"


def needs(path):
    return pytest.mark.skipif(not path.is_file(), reason=f"{path} is absent (set GI_ASSETS)")


# -- independent counts from the source text ----------------------------------------------------

def obj_counts(obj):
    """Triangles (after fan triangulation), faces, group names, materials used, mtllib files."""
    triangles = faces = 0
    groups, used, mtllibs = [], [], []
    for line in obj.read_text(errors="replace").splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "f":
            faces += 1
            triangles += len(words) - 3
        elif words[0] in ("g", "o") and len(words) > 1 and words[1] not in groups:
            groups.append(words[1])
        elif words[0] == "usemtl" and words[1] not in used:
            used.append(words[1])
        elif words[0] == "mtllib":
            mtllibs += words[1:]
    defined = []
    for name in mtllibs:
        mtl = obj.parent / name
        if mtl.is_file():
            defined += re.findall(r"^\s*newmtl\s+(\S+)", mtl.read_text(errors="replace"), re.M)
    return dict(triangles=triangles, faces=faces, groups=groups, used=used, materials=defined)


def usd_counts(path):
    stage = Usd.Stage.Open(str(path))
    meshes = [UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    counts = [np.asarray(m.GetFaceVertexCountsAttr().Get()) for m in meshes]
    materials = [p for p in stage.Traverse() if p.IsA(UsdShade.Material)]
    return stage, meshes, dict(faces=sum(len(c) for c in counts), triangles=int(sum((c - 2).sum() for c in counts)),
                               materials=len(materials))


def check_normals(meshes):
    for mesh in meshes:
        primvar = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("normals")
        assert primvar and primvar.HasValue(), f"{mesh.GetPath()} has no normals"
        values = np.asarray(primvar.Get())
        assert np.isfinite(values).all(), f"{mesh.GetPath()}: NaN normals"
        assert (np.linalg.norm(values, axis=1) > 1e-6).all(), f"{mesh.GetPath()}: zero-length normals"
        flat = primvar.ComputeFlattened()
        per_corner = primvar.GetInterpolation() == UsdGeom.Tokens.faceVarying
        expected = mesh.GetFaceVertexIndicesAttr().Get() if per_corner else mesh.GetPointsAttr().Get()
        assert flat is not None and len(flat) == len(expected)


def check_textures(stage):
    files = []
    for prim in stage.Traverse():
        shader = UsdShade.Shader(prim)
        if shader and shader.GetShaderId() == "UsdUVTexture":
            asset = shader.GetInput("file").Get()
            assert asset.resolvedPath and os.path.isfile(asset.resolvedPath), f"{prim.GetPath()}: {asset.path}"
            files.append(asset.resolvedPath)
    return files


# -- the shared assets --------------------------------------------------------------------------

@needs(SIBENIK)
def test_sibenik_keeps_counts_textures_and_normals(tmp_path):
    source = obj_counts(SIBENIK)
    out = tmp_path / "sibenik.usdc"
    report = import_file(SIBENIK, out)
    stage, meshes, counts = usd_counts(out)
    assert counts["triangles"] == source["triangles"] == 73564
    assert counts["faces"] == source["faces"]
    assert counts["materials"] == len(source["materials"]) == 15
    assert len(meshes) == len(source["used"]) == 14  # one mesh per (group, material) pair
    assert sorted(str(m.GetPath().name) for m in meshes) == sorted(source["used"])
    check_normals(meshes)
    textures = check_textures(stage)
    mtl = (SIBENIK.parent / "sibenik.mtl").read_text(errors="replace")
    named = {m for m in re.findall(r"^\s*(?:map_Kd|map_bump|bump)\s+(\S+)", mtl, re.M)}
    assert {Path(t).name for t in textures} == named
    assert not any(str(ROOT) in t for t in report.textures), "textures must stay in the asset folder"
    layer = stage.GetRootLayer()
    assert UsdGeom.GetStageUpAxis(stage) == "Y" and UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert "Marko Dabrovic" in layer.documentation
    assert "Marko Dabrovic" in layer.customLayerData["gi:import"]["credits"]


@needs(SIBENIK)
def test_obj_materials_map_mtl_sensibly(tmp_path):
    out = tmp_path / "sibenik.usda"
    import_file(SIBENIK, out)
    stage = Usd.Stage.Open(str(out))

    def surface(name):
        return UsdShade.Shader(stage.GetPrimAtPath(f"/sibenik/Materials/{name}/PreviewSurface"))

    glass = surface("staklo")  # d 0.1, Ni 1.5, Ns 256, Ks 0.78
    assert glass.GetInput("opacity").Get() == pytest.approx(0.1)
    assert glass.GetInput("opacityMode").Get() == "transparent"
    assert glass.GetInput("ior").Get() == pytest.approx(1.5)
    assert glass.GetInput("useSpecularWorkflow").Get() == 1
    assert glass.GetInput("specularColor").Get()[0] == pytest.approx(0.784314)
    assert glass.GetInput("roughness").Get() < surface("sprljci").GetInput("roughness").Get()  # Ns 256 vs 8
    green = surface("staklo_zeleno")  # d 1 but illum 4 with a green transmission filter: glass
    assert green.GetInput("opacityMode").Get() == "transparent" and green.GetInput("opacity").Get() < 1
    stone = surface("kamen_zid")  # map_Kd kamen.png, bump kamen-bump.png
    source = stone.GetInput("diffuseColor").GetConnectedSource()
    texture = UsdShade.Shader(source[0].GetPrim())
    assert texture.GetInput("file").Get().path.endswith("kamen.png")
    assert texture.GetInput("sourceColorSpace").Get() == "sRGB"
    assert stage.GetPrimAtPath("/sibenik/Materials/kamen_zid/bumpTexture")
    assert not stone.GetInput("opacity")  # opaque materials author no opacity


@needs(STAKLO)
def test_window_glass_without_normals_gets_face_normals(tmp_path):
    out = tmp_path / "staklo.usdc"
    report = import_file(STAKLO, out)
    _, meshes, counts = usd_counts(out)
    assert counts["triangles"] == obj_counts(STAKLO)["triangles"] == 1719
    check_normals(meshes)
    assert not any("normals replaced" in w for w in report.warnings)  # absent, not broken


@needs(SPONZA)
def test_sponza_keeps_its_groups(tmp_path):
    source = obj_counts(SPONZA)
    out = tmp_path / "sponza.usdc"
    report = import_file(SPONZA, out)
    stage, meshes, counts = usd_counts(out)
    assert counts["triangles"] == source["triangles"] == 66454
    assert len(meshes) == len(source["groups"]) == 34
    assert sorted(m.GetPath().name for m in meshes) == sorted(source["groups"])
    assert counts["materials"] == len(source["materials"]) == 0
    check_normals(meshes)
    assert any("normals replaced" in w for w in report.warnings)  # the source has 4 zero-length ones
    for mesh in meshes:
        assert mesh.GetSubdivisionSchemeAttr().Get() == "none"
        assert UsdGeom.PrimvarsAPI(mesh).GetPrimvar("st").GetInterpolation() == "faceVarying"


@needs(SIBENIK)
def test_reimport_gives_identical_bytes(tmp_path):
    out = tmp_path / "sibenik.usdc"
    import_file(SIBENIK, out)
    first = out.read_bytes()
    out.unlink()
    import_file(SIBENIK, out)
    assert out.read_bytes() == first


@needs(SIBENIK)
def test_import_command_and_asset_root(tmp_path, monkeypatch):
    proc = run_gi("import", "sibenik/sibenik.obj", "--assets", ASSETS, "-o", tmp_path / "s.usdc")
    assert "73564 triangles" in proc.stdout and "15 materials" in proc.stdout
    monkeypatch.setenv("GI_ASSETS", str(ASSETS))
    run_gi("import", "sibenik/extras/staklo.obj", "-o", tmp_path / "t.usdc")
    assert (tmp_path / "t.usdc").is_file()


@pytest.mark.parametrize("scene", ["sibenik", "sponza"])
def test_scene_layers_load(scene):
    generated = ROOT / "scenes" / scene / "generated"
    if not generated.is_dir():
        pytest.skip(f"{generated} not imported (scripts/import-scenes.sh)")
    from gi.inspect import inspect_scene
    report = inspect_scene(ROOT / "scenes" / scene / f"{scene}.usda")
    assert report["camera"] == "/Camera" and report["resolution"] == (1024, 768)
    assert report["lights"]["distant"] == 1 and report["dome_lights"] == 1
    assert all(resolved for resolved in report["textures"].values())
    if scene == "sibenik":
        assert report["counts"]["triangles"] == 73564 + 1719
        assert report["lights"]["rect"] > 40 and report["caustic_paths"]
    else:
        assert report["counts"]["triangles"] == 66454
        assert report["counts"]["materials"] >= 5 and not report["caustic_paths"]


# -- small sources written by the tests ---------------------------------------------------------

def test_obj_bad_normals_are_repaired(tmp_path):
    obj = tmp_path / "bad.obj"
    # (tinyobjloader reads "nan" as 0, so NaN normals are tested on glTF below.)
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 0\nvn 0 0 0\nvn 0 0 1\nvt 0 0\nvt 1 1\n"
                   "g quad\nf 1/1/1 2/2/2 3/1/3 4/2/3\ng tri\nf 1//3 2//3 3//3\n")
    report = import_file(obj, tmp_path / "bad.usda")
    _, meshes, counts = usd_counts(tmp_path / "bad.usda")
    assert counts["faces"] == 2 and counts["triangles"] == 3 and len(meshes) == 2
    check_normals(meshes)
    assert any("2 zero-length or NaN normals replaced" in w for w in report.warnings)
    quad = next(m for m in meshes if m.GetPath().name == "quad")
    normals = UsdGeom.PrimvarsAPI(quad).GetPrimvar("normals").ComputeFlattened()
    assert np.allclose(np.asarray(normals), [0, 0, 1])  # the face normal stands in
    tri = next(m for m in meshes if m.GetPath().name == "tri")
    assert not UsdGeom.PrimvarsAPI(tri).GetPrimvar("st")  # no uvs in the source, none written


def test_a_material_missing_from_the_mtl_is_named(tmp_path):
    # McGuire's CornellBox-Glossy-Floor.obj names CornellBox-Glossy.mtl, which has no "light": its
    # light panel imported grey, and the box rendered black with no word of why.
    (tmp_path / "box.mtl").write_text("newmtl wall\nKd 0.5 0.5 0.5\n")
    obj = tmp_path / "box.obj"
    obj.write_text("mtllib box.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                   "g wall\nusemtl wall\nf 1 2 3\ng light\nusemtl light\nf 1 3 4\n")
    report = import_file(obj, tmp_path / "box.usda")
    missing = [w for w in report.warnings if "has no material of the .mtl" in w]
    assert len(missing) == 1 and "'light'" in missing[0] and "box.obj" in missing[0], report.warnings
    stage = Usd.Stage.Open(str(tmp_path / "box.usda"))
    light = next(p for p in stage.Traverse() if p.GetName() == "light")
    assert not UsdShade.MaterialBindingAPI(light).GetDirectBinding().GetMaterial()
    # Rendered, the scene says why its image is black, naming the file.
    proc = run_gi("render", tmp_path / "box.usda", "--spp", 1, "--resolution", 8, 8, "-o", tmp_path / "box.exr")
    assert f"{tmp_path / 'box.usda'}: no lights and no emissive surfaces" in proc.stderr, proc.stderr


def test_bad_input_names_the_file(tmp_path):
    missing = tmp_path / "nothing.obj"
    with pytest.raises(ImportError_, match=re.escape(str(missing))):
        import_file(missing, tmp_path / "x.usdc")
    broken = tmp_path / "broken.gltf"
    broken.write_text("{ this is not json")
    with pytest.raises(ImportError_, match=re.escape(str(broken))):
        import_file(broken, tmp_path / "x.usdc")
    bad_index = tmp_path / "index.obj"
    bad_index.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    with pytest.raises(ImportError_, match="index.obj"):
        import_file(bad_index, tmp_path / "x.usdc")
    proc = run_gi("import", broken, "-o", tmp_path / "x.usdc", check=False)
    assert proc.returncode == 2 and str(broken) in proc.stderr
    assert not (tmp_path / "x.usdc").exists()


# 1x1 RGBA PNG (an opaque orange pixel).
PNG = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z/C/HgAGgwJ/lK3Q6wAAAABJRU5ErkJggg==")


def write_gltf(path, zero_normal=True, external_image=None):
    """A quad (two triangles, indexed) in a child node translated by (1, 2, 3), with a base colour
    texture (embedded as a data URI, or an external file) and metallic-roughness factors."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    normals = np.array([[0, 0, 1]] * 4, np.float32)
    if zero_normal:
        normals[1] = np.nan
        normals[2] = 0
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)  # glTF: v runs down
    indices = np.array([0, 1, 2, 0, 2, 3], np.uint16)
    blob = positions.tobytes() + normals.tobytes() + uvs.tobytes() + indices.tobytes()
    views = [(0, 48), (48, 48), (96, 32), (128, 12)]
    image = {"uri": external_image} if external_image else \
        {"uri": "data:image/png;base64," + base64.b64encode(PNG).decode(), "name": "orange"}
    gltf = {
        "asset": {"version": "2.0", "generator": "test_import", "copyright": "test copyright"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "root", "children": [1]},
                  {"name": "quad node", "mesh": 0, "translation": [1, 2, 3]}],
        "meshes": [{"name": "quad", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                                    "indices": 3, "material": 0}]}],
        "materials": [{"name": "painted", "doubleSided": True,
                       "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0.25,
                                                "roughnessFactor": 0.75, "baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"wrapS": 33071, "wrapT": 10497}],
        "images": [image],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }
    path.write_text(json.dumps(gltf))
    return path


def test_gltf_meshes_nodes_and_metallic_roughness(tmp_path):
    source = write_gltf(tmp_path / "quad.gltf")
    out = tmp_path / "out" / "quad.usda"
    report = import_file(source, out)
    stage, meshes, counts = usd_counts(out)
    assert counts == dict(faces=2, triangles=2, materials=1) and len(meshes) == 1
    mesh = meshes[0]
    assert str(mesh.GetPath()) == "/quad/root/quad_node/quad"
    world = UsdGeom.Xformable(mesh).ComputeLocalToWorldTransform(Usd.TimeCode.Default())
    assert tuple(world.ExtractTranslation()) == (1, 2, 3)
    check_normals(meshes)
    assert any("2 zero-length or NaN normals replaced" in w for w in report.warnings)
    st = np.asarray(UsdGeom.PrimvarsAPI(mesh).GetPrimvar("st").Get())
    assert np.allclose(st, [[0, 0], [1, 0], [1, 1], [0, 1]])  # flipped to USD's t-up
    assert mesh.GetDoubleSidedAttr().Get()
    surface = UsdShade.Shader(stage.GetPrimAtPath("/quad/Materials/painted/PreviewSurface"))
    assert surface.GetInput("useSpecularWorkflow").Get() == 0
    assert surface.GetInput("metallic").Get() == pytest.approx(0.25)
    assert surface.GetInput("roughness").Get() == pytest.approx(0.75)
    textures = check_textures(stage)
    assert len(textures) == 1 and Path(textures[0]).read_bytes() == PNG  # the embedded image, written out
    texture = UsdShade.Shader(stage.GetPrimAtPath("/quad/Materials/painted/baseColorTexture"))
    assert texture.GetInput("wrapS").Get() == "clamp" and texture.GetInput("wrapT").Get() == "repeat"
    assert tuple(texture.GetInput("scale").Get()) == (0.5, 0.5, 0.5, 1)
    assert "test copyright" in stage.GetRootLayer().customLayerData["gi:import"]["credits"]
    first = out.read_bytes()
    import_file(source, out)
    assert out.read_bytes() == first


def test_gltf_external_image_is_referenced_not_copied(tmp_path):
    (tmp_path / "tex").mkdir()
    (tmp_path / "tex" / "my image.png").write_bytes(PNG)
    source = write_gltf(tmp_path / "quad.gltf", zero_normal=False, external_image="tex/my%20image.png")
    out = tmp_path / "out" / "quad.usdc"
    report = import_file(source, out)
    stage = Usd.Stage.Open(str(out))
    assert check_textures(stage) == [str(tmp_path / "tex" / "my image.png")]
    assert not (tmp_path / "out" / "quad_textures").exists()
    assert not any("normals replaced" in w for w in report.warnings)
    layer = Sdf.Layer.FindOrOpen(str(out))
    assert "../tex/my image.png" in layer.ExportToString()


def test_gltf_renders(tmp_path):
    """The imported layer goes through the loader into the renderer."""
    from gi.loader import load_stage
    out = tmp_path / "quad.usdc"
    import_file(write_gltf(tmp_path / "quad.gltf"), out)
    loaded = load_stage(out)
    assert loaded.counts["triangles"] == 2 and loaded.counts["materials"] == 1
    assert all(loaded.textures.values())


def test_glb_binary_container(tmp_path):
    gltf = json.loads(write_gltf(tmp_path / "quad.gltf").read_text())
    blob = base64.b64decode(gltf["buffers"][0]["uri"].split(",", 1)[1])
    gltf["buffers"][0] = {"byteLength": len(blob)}
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    glb = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(blob))
    glb += struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    (tmp_path / "quad.glb").write_bytes(glb)
    _, meshes, counts = usd_counts(import_file(tmp_path / "quad.glb", tmp_path / "glb.usdc").output)
    assert counts["triangles"] == 2 and len(meshes) == 1
