"""Per-face materials through UsdGeomSubset (family "materialBind") in gi.loader: each subset is a
mesh piece of its own with its own material, the faces in none keep the mesh's material.
Stages are written with pxr into tmp_path; the render tests need the compiled core."""
import numpy as np
import pytest
from pxr import Gf, Sdf, UsdGeom, UsdShade, Vt

from conftest import new_stage, render
from gi import descriptors, load_stage

needs_core = pytest.mark.skipif(not descriptors.HAVE_CORE, reason="gi._core is not built")

BIG_QUAD = [(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)]  # fills the default camera's view from z=5
# Three vertical strips x in [-3,-1], [-1,1], [1,3]: faces 0, 1, 2 (left to right).
STRIP_POINTS = [(x, y, 0) for x in (-3, -1, 1, 3) for y in (-3, 3)]   # point 2i: (x_i, -3), 2i+1: (x_i, 3)
STRIP_INDICES = [0, 2, 3, 1, 2, 4, 5, 3, 4, 6, 7, 5]


# -- helpers -------------------------------------------------------------------------------------

def define_mesh(stage, path, points, counts, indices):
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreatePointsAttr(points)
    mesh.CreateFaceVertexCountsAttr(list(counts))
    mesh.CreateFaceVertexIndicesAttr(list(indices))
    return mesh


def strips(stage, path="/Strips"):
    return define_mesh(stage, path, STRIP_POINTS, [4, 4, 4], STRIP_INDICES)


def material(stage, path, emissive=None, diffuse=(0.0, 0.0, 0.0), **inputs):
    """A UsdPreviewSurface material; emissive ones show their colour directly, with no light."""
    result = UsdShade.Material.Define(stage, path)
    surface = UsdShade.Shader.Define(stage, f"{path}/Surface")
    surface.CreateIdAttr("UsdPreviewSurface")
    surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(*diffuse))
    if emissive is not None:
        surface.CreateInput("emissiveColor", Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(*emissive))
    for name, (type_name, value) in inputs.items():
        surface.CreateInput(name, type_name).Set(value)
    result.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")
    return result


def read_through_st(stage, bound, file):
    """Drives `bound`'s diffuseColor by a texture read through a UsdPrimvarReader_float2 of st: the
    mesh's texture coordinates are those the readers of its materials (subsets' included) name."""
    path = bound.GetPath()
    reader = UsdShade.Shader.Define(stage, path.AppendChild("Reader"))
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    reader.CreateInput("varname", Sdf.ValueTypeNames.String).Set("st")
    reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    texture = UsdShade.Shader.Define(stage, path.AppendChild("Texture"))
    texture.CreateIdAttr("UsdUVTexture")
    texture.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(str(file))
    texture.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(reader.ConnectableAPI(), "result")
    texture.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
    surface = UsdShade.Shader(stage.GetPrimAtPath(path.AppendChild("Surface")))
    surface.GetInput("diffuseColor").ConnectToSource(texture.ConnectableAPI(), "rgb")
    return bound


def bind(prim, bound):
    UsdShade.MaterialBindingAPI.Apply(prim.GetPrim()).Bind(bound)


def subset(mesh, name, faces, bound=None):
    """A materialBind face subset of `mesh` (bound to `bound` if given)."""
    result = UsdShade.MaterialBindingAPI(mesh.GetPrim()).CreateMaterialBindSubset(name, Vt.IntArray(list(faces)))
    if bound is not None:
        bind(result, bound)
    return result


def load(stage, path, fake_scene):
    stage.Save()
    return load_stage(path, scene=fake_scene)


def material_name(scene, mesh):
    return scene.materials[mesh.material].name if mesh.material >= 0 else None


def corners(mesh):
    """Each triangle's corner positions, rounded, as a sorted tuple (winding-independent)."""
    p = np.asarray(mesh.positions, np.float64)[np.asarray(mesh.indices)]
    return sorted(tuple(sorted(map(tuple, np.round(t, 6)))) for t in p)


def strip_x_ranges(mesh):
    """The x extent of each triangle of a recorded mesh."""
    p = np.asarray(mesh.positions)[np.asarray(mesh.indices)]
    return sorted({(float(t[:, 0].min()), float(t[:, 0].max())) for t in p})


def no_unsupported_warning(loaded):
    assert not any("not supported" in w for w in loaded.warnings), loaded.warnings


# -- splitting -----------------------------------------------------------------------------------

def test_each_subset_is_a_piece_with_its_own_material(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = define_mesh(stage, "/Quad", BIG_QUAD, [3, 3], [0, 1, 2, 0, 2, 3])
    bind(mesh, material(stage, "/Looks/Blue", emissive=(0, 0, 1)))
    subset(mesh, "Red", [0], material(stage, "/Looks/Red", emissive=(1, 0, 0)))
    subset(mesh, "Green", [1], material(stage, "/Looks/Green", emissive=(0, 1, 0)))
    loaded = load(stage, path, fake_scene)
    assert loaded.warnings == []
    assert [m.name for m in fake_scene.meshes] == ["/Quad/Red", "/Quad/Green"]  # no faces left for /Quad
    assert material_name(fake_scene, fake_scene.mesh("/Quad/Red")) == "/Looks/Red"
    assert material_name(fake_scene, fake_scene.mesh("/Quad/Green")) == "/Looks/Green"
    p = [tuple(map(float, v)) for v in BIG_QUAD]
    assert corners(fake_scene.mesh("/Quad/Red")) == [tuple(sorted([p[0], p[1], p[2]]))]
    assert corners(fake_scene.mesh("/Quad/Green")) == [tuple(sorted([p[0], p[2], p[3]]))]
    assert loaded.counts["meshes"] == 1 and loaded.counts["triangles"] == 2


@needs_core
def test_two_subsets_render_red_and_green(tmp_path):
    stage, path = new_stage(tmp_path)
    mesh = define_mesh(stage, "/Quad", BIG_QUAD, [3, 3], [0, 1, 2, 0, 2, 3])  # lower right, upper left
    bind(mesh, material(stage, "/Looks/Blue", emissive=(0, 0, 1)))
    subset(mesh, "Red", [0], material(stage, "/Looks/Red", emissive=(1, 0, 0)))
    subset(mesh, "Green", [1], material(stage, "/Looks/Green", emissive=(0, 1, 0)))
    stage.Save()
    image, _, loaded = render(path, spp=4)
    assert loaded.warnings == []
    assert np.allclose(image[28, 28], (1, 0, 0), atol=0.02)   # bottom right: face 0
    assert np.allclose(image[3, 3], (0, 1, 0), atol=0.02)     # top left: face 1
    assert image[..., 2].max() < 0.02                          # the mesh's own blue is used nowhere


def test_faces_in_no_subset_keep_the_mesh_material(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    bind(mesh, material(stage, "/Looks/White", diffuse=(0.8, 0.8, 0.8)))
    subset(mesh, "Middle", [1], material(stage, "/Looks/Red", diffuse=(0.8, 0.1, 0.1)))
    loaded = load(stage, path, fake_scene)
    assert loaded.warnings == []
    no_unsupported_warning(loaded)
    rest, middle = fake_scene.mesh("/Strips"), fake_scene.mesh("/Strips/Middle")
    assert len(fake_scene.meshes) == 2
    assert material_name(fake_scene, rest) == "/Looks/White" and material_name(fake_scene, middle) == "/Looks/Red"
    assert strip_x_ranges(rest) == [(-3, -1), (1, 3)] and len(rest.indices) == 4
    assert strip_x_ranges(middle) == [(-1, 1)] and len(middle.indices) == 2
    assert len(middle.positions) == 4 and len(rest.positions) == 8   # each piece keeps only its vertices
    assert loaded.counts["meshes"] == 1 and loaded.counts["triangles"] == 6


@needs_core
def test_partial_subset_renders_over_the_mesh_material(tmp_path):
    stage, path = new_stage(tmp_path)
    UsdGeom.Xformable(stage.GetPrimAtPath("/Camera")).GetOrderedXformOps()[0].Set(Gf.Vec3d(0, 0, 20))
    mesh = strips(stage)
    bind(mesh, material(stage, "/Looks/White", emissive=(1, 1, 1)))
    subset(mesh, "Middle", [1], material(stage, "/Looks/Red", emissive=(1, 0, 0)))
    stage.Save()
    image, _, loaded = render(path, spp=4)
    assert loaded.warnings == []
    row = image[16]
    # From z=20 the three strips are pixels ~4-12, ~13-18 and ~19-27 of the middle row, background beyond.
    assert np.allclose(row[6:11], 1, atol=0.02)                 # left strip: the mesh's white
    assert np.allclose(row[15:18], (1, 0, 0), atol=0.02)        # middle strip: the subset's red
    assert np.allclose(row[21:26], 1, atol=0.02)                # right strip: the mesh's white
    assert np.allclose(row[:2], 0) and np.allclose(row[-2:], 0)


def test_a_subset_without_a_binding_and_other_families_keep_the_mesh_material(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    bind(mesh, material(stage, "/Looks/White", diffuse=(0.8, 0.8, 0.8)))
    subset(mesh, "Unbound", [0])                                      # inherits the mesh's binding
    UsdGeom.Subset.CreateGeomSubset(mesh, "Custom", UsdGeom.Tokens.face, Vt.IntArray([2]), "myFamily")
    loaded = load(stage, path, fake_scene)
    assert loaded.warnings == []
    assert sorted(m.name for m in fake_scene.meshes) == ["/Strips", "/Strips/Unbound"]
    assert all(material_name(fake_scene, m) == "/Looks/White" for m in fake_scene.meshes)
    assert len(fake_scene.mesh("/Strips").indices) == 4   # the custom-family face stays in the mesh


def test_subset_binding_honours_material_purpose(tmp_path, fake_scene):
    """A subset's preview-purpose binding is not the full (render) binding: its full one wins."""
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    bind(mesh, material(stage, "/Looks/White", diffuse=(0.8, 0.8, 0.8)))
    middle = subset(mesh, "Middle", [1])
    api = UsdShade.MaterialBindingAPI.Apply(middle.GetPrim())
    api.Bind(material(stage, "/Looks/Preview", diffuse=(0, 0, 1)), materialPurpose=UsdShade.Tokens.preview)
    api.Bind(material(stage, "/Looks/Full", diffuse=(1, 0, 0)), materialPurpose=UsdShade.Tokens.full)
    load(stage, path, fake_scene)
    assert material_name(fake_scene, fake_scene.mesh("/Strips/Middle")) == "/Looks/Full"


# -- primvars ------------------------------------------------------------------------------------

def fv_values(face, corner):
    """A distinct face-varying value for each (face, corner)."""
    return (face / 10, corner / 10)


@pytest.mark.parametrize("interpolation", ["faceVarying", "vertex"])
def test_normals_and_uvs_survive_the_split(tmp_path, fake_scene, interpolation):
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    api = UsdGeom.PrimvarsAPI(mesh)
    if interpolation == "faceVarying":
        uvs = [fv_values(f, k) for f in range(3) for k in range(4)]
        normals = [(f / 10, k / 10, 1) for f in range(3) for k in range(4)]
        st = api.CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying)
        st.Set(uvs[::-1])
        st.SetIndices(Vt.IntArray(list(range(11, -1, -1))))  # indexed: exercised de-indexing too
        expected = {(f, STRIP_INDICES[4 * f + k]): (uvs[4 * f + k], normals[4 * f + k])
                    for f in range(3) for k in range(4)}
    else:
        uvs = [(p[0] / 10, p[1] / 10) for p in STRIP_POINTS]
        normals = [(p[0] / 10, p[1] / 10, 1) for p in STRIP_POINTS]
        api.CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex).Set(uvs)
        expected = {(f, STRIP_INDICES[4 * f + k]): (uvs[STRIP_INDICES[4 * f + k]], normals[STRIP_INDICES[4 * f + k]])
                    for f in range(3) for k in range(4)}
    api.CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray, interpolation).Set(normals)
    (tmp_path / "red.png").write_bytes(b"not read: the loader only checks it exists")
    red = read_through_st(stage, material(stage, "/Looks/Red", diffuse=(0.8, 0.1, 0.1)), tmp_path / "red.png")
    subset(mesh, "Right", [2], red)
    subset(mesh, "Left", [0], material(stage, "/Looks/Green", diffuse=(0.1, 0.8, 0.1)))
    loaded = load(stage, path, fake_scene)
    assert loaded.warnings == []
    faces_of_piece = {"/Strips/Left": 0, "/Strips": 1, "/Strips/Right": 2}
    assert sorted(m.name for m in fake_scene.meshes) == sorted(faces_of_piece)
    for name, face in faces_of_piece.items():
        piece = fake_scene.mesh(name)
        assert piece.normals is not None and piece.uvs is not None, name
        assert len(piece.normals) == len(piece.uvs) == len(piece.positions), name
        assert len(piece.indices) == 2, name
        seen = set()
        for vertex in np.unique(piece.indices):
            point = STRIP_POINTS.index(tuple(int(c) for c in piece.positions[vertex]))
            uv, normal = expected[(face, point)]
            n = np.asarray(normal, np.float64) / np.linalg.norm(normal)
            assert np.allclose(piece.uvs[vertex], uv, atol=1e-6), (name, point)
            assert (np.allclose(piece.normals[vertex], normal, atol=1e-6)
                    or np.allclose(piece.normals[vertex], n, atol=1e-6)), (name, point)
            seen.add(point)
        assert seen == {STRIP_INDICES[4 * face + k] for k in range(4)}, name


# -- bad subsets ---------------------------------------------------------------------------------

def test_bad_subsets_warn_naming_the_subset_and_still_load(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    bind(mesh, material(stage, "/Looks/White", diffuse=(0.8, 0.8, 0.8)))
    subset(mesh, "First", [0, 7, -1], material(stage, "/Looks/Red", diffuse=(0.8, 0.1, 0.1)))
    subset(mesh, "Second", [0, 1, 1], material(stage, "/Looks/Green", diffuse=(0.1, 0.8, 0.1)))
    subset(mesh, "Empty", [], material(stage, "/Looks/Blue", diffuse=(0.1, 0.1, 0.8)))
    subset(mesh, "AllBad", [3, 99], material(stage, "/Looks/Blue", diffuse=(0.1, 0.1, 0.8)))
    loaded = load(stage, path, fake_scene)
    file = str(path)

    def warnings_of(prim):
        return [w for w in loaded.warnings if w.startswith(f"{file}: {prim}: ")]
    first, second = warnings_of("/Strips/First"), warnings_of("/Strips/Second")
    assert len(first) == 1 and "out of range" in first[0] and "3 faces" in first[0]
    assert any("also in /Strips/First" in w and "overlap" in w for w in second), second
    assert any("more than once" in w for w in second), second
    assert len(warnings_of("/Strips/Empty")) == 1 and "no face indices" in warnings_of("/Strips/Empty")[0]
    assert len(warnings_of("/Strips/AllBad")) == 1 and "out of range" in warnings_of("/Strips/AllBad")[0]
    no_unsupported_warning(loaded)
    # Face 0 goes to the first subset claiming it; face 1 to Second; face 2 stays with the mesh.
    assert sorted(m.name for m in fake_scene.meshes) == ["/Strips", "/Strips/First", "/Strips/Second"]
    assert strip_x_ranges(fake_scene.mesh("/Strips/First")) == [(-3, -1)]
    assert strip_x_ranges(fake_scene.mesh("/Strips/Second")) == [(-1, 1)]
    assert strip_x_ranges(fake_scene.mesh("/Strips")) == [(1, 3)]
    assert material_name(fake_scene, fake_scene.mesh("/Strips/First")) == "/Looks/Red"
    assert loaded.counts["triangles"] == 6


@needs_core
def test_bad_subsets_still_render(tmp_path):
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    bind(mesh, material(stage, "/Looks/White", emissive=(1, 1, 1)))
    subset(mesh, "First", [1, 42], material(stage, "/Looks/Red", emissive=(1, 0, 0)))
    subset(mesh, "Second", [1], material(stage, "/Looks/Green", emissive=(0, 1, 0)))
    stage.Save()
    image, _, loaded = render(path, spp=4)
    assert any("/Strips/First: " in w and "out of range" in w for w in loaded.warnings), loaded.warnings
    assert any("/Strips/Second: " in w and "overlap" in w for w in loaded.warnings), loaded.warnings
    assert np.allclose(image[16, 16], (1, 0, 0), atol=0.02)   # the overlapped face: the first subset's


def test_element_type_and_partition_problems_warn(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    api = UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim())
    api.SetMaterialBindSubsetsFamilyType(UsdGeom.Tokens.partition)
    subset(mesh, "Middle", [1], material(stage, "/Looks/Red", diffuse=(0.8, 0.1, 0.1)))
    points = api.CreateMaterialBindSubset("Points", Vt.IntArray([0]), UsdGeom.Tokens.point)
    bind(points, material(stage, "/Looks/Green", diffuse=(0.1, 0.8, 0.1)))
    loaded = load(stage, path, fake_scene)
    assert any(w.startswith(f"{path}: /Strips/Points: ") and "not a face set" in w for w in loaded.warnings)
    assert any(w.startswith(f"{path}: /Strips: ") and "partition" in w and "2 faces" in w for w in loaded.warnings)
    assert sorted(m.name for m in fake_scene.meshes) == ["/Strips", "/Strips/Middle"]


def test_subsets_of_a_mesh_with_dropped_faces(tmp_path, fake_scene):
    """Face indices are authored faces even when some faces are invalid and dropped."""
    stage, path = new_stage(tmp_path)
    mesh = define_mesh(stage, "/Strips", STRIP_POINTS, [4, 2, 4, 4], STRIP_INDICES[:4] + [0, 1] + STRIP_INDICES[4:])
    subset(mesh, "Dropped", [1], material(stage, "/Looks/Green", diffuse=(0.1, 0.8, 0.1)))
    subset(mesh, "Right", [3], material(stage, "/Looks/Red", diffuse=(0.8, 0.1, 0.1)))
    loaded = load(stage, path, fake_scene)
    assert sorted(m.name for m in fake_scene.meshes) == ["/Strips", "/Strips/Right"]
    assert strip_x_ranges(fake_scene.mesh("/Strips/Right")) == [(1, 3)]
    assert strip_x_ranges(fake_scene.mesh("/Strips")) == [(-3, -1), (-1, 1)]
    assert any("fewer than 3 vertices" in w for w in loaded.warnings)


# -- instancing and inspect ----------------------------------------------------------------------

def test_subsets_in_instanced_prototypes(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = strips(stage, "/Asset/Strips")
    bind(mesh, material(stage, "/Looks/White", diffuse=(0.8, 0.8, 0.8)))
    subset(mesh, "Middle", [1], material(stage, "/Looks/Red", diffuse=(0.8, 0.1, 0.1)))
    stage.GetPrimAtPath("/Asset").SetSpecifier(Sdf.SpecifierClass)
    for i in range(2):
        instance = stage.DefinePrim(f"/Instance{i}")
        instance.GetInherits().AddInherit("/Asset")
        instance.SetInstanceable(True)
    instancer = UsdGeom.PointInstancer.Define(stage, "/Instancer")
    UsdGeom.Xform.Define(stage, "/Instancer/Proto")
    proto = strips(stage, "/Instancer/Proto/Strips")
    subset(proto, "Middle", [1], material(stage, "/Looks/Red", diffuse=(0.8, 0.1, 0.1)))
    instancer.CreatePrototypesRel().AddTarget("/Instancer/Proto")
    instancer.CreateProtoIndicesAttr([0, 0, 0])
    instancer.CreatePositionsAttr([(0, 0, 0), (10, 0, 0), (20, 0, 0)])
    loaded = load(stage, path, fake_scene)
    assert loaded.warnings == []
    assert loaded.counts["prototypes"] == 2 and loaded.counts["instances"] == 5
    assert loaded.counts["meshes"] == 2 and loaded.counts["triangles"] == 12
    assert len(fake_scene.meshes) == 4 and all(m.prototype >= 0 for m in fake_scene.meshes)
    by_name = {m.name: m for m in fake_scene.meshes}
    middles = [name for name in by_name if name.endswith("/Strips/Middle")]
    assert len(middles) == 2 and "/Instancer/Proto/Strips/Middle" in middles
    for name in middles:
        assert material_name(fake_scene, by_name[name]) == "/Looks/Red"
        assert strip_x_ranges(by_name[name]) == [(-1, 1)]
        rest = by_name[name[:-len("/Middle")]]
        assert strip_x_ranges(rest) == [(-3, -1), (1, 3)] and rest.prototype == by_name[name].prototype
    instanced = by_name[next(n for n in middles if not n.startswith("/Instancer"))]
    assert material_name(fake_scene, by_name[instanced.name[:-len("/Middle")]]) == "/Looks/White"


def test_inspect_counts_mesh_prims_and_triangles_per_subset_material(tmp_path):
    from gi.inspect import format_report, inspect_scene
    stage, path = new_stage(tmp_path)
    mesh = strips(stage)
    bind(mesh, material(stage, "/Looks/White", diffuse=(0.8, 0.8, 0.8)))
    subset(mesh, "Mirror", [0, 2], material(stage, "/Looks/Mirror", diffuse=(0, 0, 0), metallic=(
        Sdf.ValueTypeNames.Float, 1.0), roughness=(Sdf.ValueTypeNames.Float, 0.0)))
    stage.Save()
    report = inspect_scene(path)
    assert report["counts"]["meshes"] == 1 and report["counts"]["triangles"] == 6
    assert report["caustic_surfaces"] == [{"material": "/Looks/Mirror", "kind": "mirror", "triangles": 4,
                                           "spheres": 0}]
    # The subsets cost no warning; the stage, which has no light, warns of that alone.
    assert report["warnings"] == ["no lights and no emissive surfaces: every image of this scene is black"]
    assert "1 meshes, 6 triangles" in format_report(report)
