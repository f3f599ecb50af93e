"""gi.loader against a recording fake Scene (conftest.RecordingScene): runs without the compiled core.
Test stages are written with pxr into tmp_path."""
import math
import subprocess
import sys

import numpy as np
import pytest
from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade, Vt

from conftest import CORNELL, ROOT, SOURCE, new_stage
from gi import SceneError, load_stage

QUAD = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]


# -- helpers -------------------------------------------------------------------------------------

def define_mesh(stage, path, points=QUAD, counts=(4,), indices=(0, 1, 2, 3)):
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreatePointsAttr(points)
    mesh.CreateFaceVertexCountsAttr(list(counts))
    mesh.CreateFaceVertexIndicesAttr(list(indices))
    return mesh


def load(stage, path, fake_scene, **kwargs):
    stage.Save()
    return load_stage(path, scene=fake_scene, **kwargs)


def triangle_normals(mesh):
    """Unit geometric normals of a recorded mesh's triangles."""
    p = np.asarray(mesh.positions, np.float64)[np.asarray(mesh.indices)]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def triangle_corners(mesh):
    """Each triangle's corner positions as tuples, for comparing triangulations."""
    p = np.asarray(mesh.positions)[np.asarray(mesh.indices)]
    return [tuple(map(tuple, np.round(t, 6))) for t in p]


def signed_volume(mesh):
    """Positive for a closed mesh whose triangles wind counter-clockwise seen from outside."""
    p = np.asarray(mesh.positions, np.float64)[np.asarray(mesh.indices)]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6)


def define_preview_material(stage, path, **inputs):
    material = UsdShade.Material.Define(stage, path)
    surface = UsdShade.Shader.Define(stage, f"{path}/Surface")
    surface.CreateIdAttr("UsdPreviewSurface")
    for name, (type_name, value) in inputs.items():
        surface.CreateInput(name, type_name).Set(value)
    material.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")
    return material, surface


def bind(prim, material):
    UsdShade.MaterialBindingAPI.Apply(prim.GetPrim() if hasattr(prim, "GetPrim") else prim).Bind(material)


# -- the Cornell box -----------------------------------------------------------------------------

SPEC_WALLS = {  # spec section 2: v0..v3 and the inward normal
    "/World/Floor": ([(-1, -1, -1), (-1, -1, 1), (1, -1, 1), (1, -1, -1)], (0, 1, 0)),
    "/World/Ceiling": ([(-1, 1, -1), (1, 1, -1), (1, 1, 1), (-1, 1, 1)], (0, -1, 0)),
    "/World/BackWall": ([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)], (0, 0, 1)),
    "/World/LeftWall": ([(-1, -1, -1), (-1, 1, -1), (-1, 1, 1), (-1, -1, 1)], (1, 0, 0)),
    "/World/RightWall": ([(1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1)], (-1, 0, 0)),
}
SPEC_ALBEDO = {"/World/Looks/White": (0.73, 0.73, 0.73), "/World/Looks/Red": (0.65, 0.05, 0.05),
               "/World/Looks/Blue": (0.05, 0.05, 0.65)}


@pytest.fixture
def cornell_loaded(fake_scene):
    return load_stage(CORNELL, scene=fake_scene), fake_scene


def test_cornell_counts(cornell_loaded):
    loaded, scene = cornell_loaded
    assert loaded.warnings == []
    assert len(scene.meshes) == 5 and len(scene.spheres) == 1 and len(scene.lights) == 1
    assert len(scene.materials) == 4 and len(scene.cameras) == 1 and scene.instances == []
    assert loaded.counts == dict(meshes=5, triangles=10, spheres=1, lights=1, instances=0, materials=4,
                                 prototypes=0)
    assert loaded.light_kinds == {"rect": 1}
    assert loaded.resolution == (512, 512) and loaded.camera_path == "/World/Camera"


def test_cornell_walls_have_the_spec_vertices_and_face_inward(cornell_loaded):
    _, scene = cornell_loaded
    for name, (quad, inward) in SPEC_WALLS.items():
        mesh = scene.mesh(name)
        v0, v1, v2, v3 = quad
        assert sorted(triangle_corners(mesh)) == sorted([(v0, v1, v2), (v0, v2, v3)]), name
        assert np.allclose(triangle_normals(mesh), inward), name
        assert mesh.double_sided and np.allclose(mesh.transform, np.eye(4))
        assert mesh.normals is None and mesh.uvs is None


def test_cornell_materials_match_the_spec(cornell_loaded):
    _, scene = cornell_loaded
    for wall, material in [("/World/Floor", "/World/Looks/White"), ("/World/Ceiling", "/World/Looks/White"),
                           ("/World/BackWall", "/World/Looks/White"), ("/World/LeftWall", "/World/Looks/Red"),
                           ("/World/RightWall", "/World/Looks/Blue")]:
        desc = scene.material_of(wall)
        assert desc.name == material
        assert np.allclose(desc.diffuse_color, SPEC_ALBEDO[material])
        assert desc.use_specular_workflow and np.allclose(desc.specular_color, 0) and desc.roughness == 1
        assert desc.opacity == 1 and np.allclose(desc.emissive_color, 0)
    glass = scene.material_of("/World/GlassSphere")
    assert glass.name == "/World/Looks/Glass"
    assert glass.opacity == 0 and glass.opacity_mode == "transparent"
    assert glass.ior == pytest.approx(1.5) and glass.roughness == 0 and glass.metallic == 0
    assert np.allclose(glass.diffuse_color, (0.6, 0.9, 0.6))


def test_cornell_sphere_is_exact_and_rests_on_the_floor(cornell_loaded):
    _, scene = cornell_loaded
    sphere = scene.spheres[0]
    assert sphere.name == "/World/GlassSphere" and sphere.center == (0, 0, 0)
    assert sphere.radius == pytest.approx(0.4)
    assert np.allclose(sphere.transform[3, :3], (0, -0.6, 0))


def test_cornell_light_is_the_spec_rect_facing_down(cornell_loaded):
    _, scene = cornell_loaded
    light = scene.lights[0]
    assert (light.name, light.kind) == ("/World/Light", "rect")
    assert light.width == pytest.approx(0.46) and light.height == pytest.approx(0.38)
    assert light.intensity == 15 and light.exposure == 0 and not light.normalize
    assert np.allclose(light.color, 1) and light.visible_to_camera and light.texture_file == ""
    m = np.asarray(light.transform)
    assert np.allclose(np.array([0, 0, -1, 0]) @ m, (0, -1, 0, 0))  # emits along local -Z = world -Y
    corners = np.array([[-0.23, -0.19, 0, 1], [0.23, 0.19, 0, 1]]) @ m
    assert np.allclose(corners[:, 1], 0.99)
    assert np.allclose(sorted(corners[:, 0]), (-0.23, 0.23)) and np.allclose(sorted(corners[:, 2]), (-0.19, 0.19))


def test_cornell_camera_has_the_spec_field_of_view(cornell_loaded):
    _, scene = cornell_loaded
    camera = scene.cameras[0]
    assert camera.name == "/World/Camera" and camera.projection == "perspective" and camera.f_stop == 0
    for aperture in (camera.horizontal_aperture, camera.vertical_aperture):
        fov = math.degrees(2 * math.atan(aperture / 2 / camera.focal_length))
        assert fov == pytest.approx(39.3077, abs=1e-3)
    assert np.allclose(camera.transform, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 3.9, 1]])


# -- meshes --------------------------------------------------------------------------------------

def test_quad_and_pentagon_are_fan_triangulated(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),                  # quad
              (2, 0, 0), (3, 0, 0), (3.5, 1, 0), (2.5, 2, 0), (1.5, 1, 0)]  # pentagon
    define_mesh(stage, "/Shapes", points, counts=[4, 5], indices=[0, 1, 2, 3, 4, 5, 6, 7, 8])
    loaded = load(stage, path, fake_scene)
    mesh = fake_scene.mesh("/Shapes")
    p = [tuple(map(float, points[i])) for i in range(len(points))]
    fans = [(p[0], p[1], p[2]), (p[0], p[2], p[3]), (p[4], p[5], p[6]), (p[4], p[6], p[7]), (p[4], p[7], p[8])]
    assert triangle_corners(mesh) == fans
    assert loaded.counts["triangles"] == 5 and loaded.warnings == []


def test_face_varying_normals_are_de_indexed_per_corner(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = define_mesh(stage, "/Quad")
    normals = UsdGeom.PrimvarsAPI(mesh).CreatePrimvar("normals", Sdf.ValueTypeNames.Normal3fArray,
                                                      UsdGeom.Tokens.faceVarying)
    normals.Set([(0, 0, 1), (0, 1, 0)])
    normals.SetIndices(Vt.IntArray([0, 1, 0, 1]))  # corners 0, 2 -> +Z; corners 1, 3 -> +Y
    mesh.CreateNormalsAttr([(1, 0, 0)] * 4)         # primvars:normals wins over this
    mesh.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    load(stage, path, fake_scene)
    recorded = fake_scene.mesh("/Quad")
    assert recorded.positions.shape == (6, 3) and recorded.normals.shape == (6, 3)
    corner_of_vertex = [0, 1, 2, 0, 2, 3]  # fan (0, 1, 2), (0, 2, 3), one vertex per corner
    expected = [(0, 0, 1) if c % 2 == 0 else (0, 1, 0) for c in corner_of_vertex]
    assert np.allclose(recorded.positions, np.array(QUAD)[corner_of_vertex])
    assert np.allclose(recorded.normals, expected)
    assert recorded.indices.dtype == np.uint32 and recorded.positions.dtype == np.float32


@pytest.mark.parametrize("interpolation, values, expected", [
    ("vertex", [(0, 0, 1), (0, 1, 0), (1, 0, 0), (0, 0, -1)], "per point"),
    ("uniform", [(0, 1, 0)], [(0, 1, 0)] * 6),
    ("constant", [(1, 0, 0)], "constant"),
])
def test_normals_of_every_interpolation(tmp_path, fake_scene, interpolation, values, expected):
    stage, path = new_stage(tmp_path)
    mesh = define_mesh(stage, "/Quad")
    mesh.CreateNormalsAttr(values)
    mesh.SetNormalsInterpolation(interpolation)
    load(stage, path, fake_scene)
    recorded = fake_scene.mesh("/Quad")
    if expected == "per point":  # shared points keep their own normals
        assert recorded.positions.shape == (4, 3)
        assert np.allclose(recorded.normals, values)
    elif expected == "constant":
        assert np.allclose(recorded.normals, values[0])
    else:
        assert np.allclose(recorded.normals, expected)


def test_uv_primvar_is_the_one_the_reader_names(tmp_path, fake_scene):
    """Indexed texture coordinates come from the primvar the material's UsdPrimvarReader_float2
    names, whatever it is called; a mesh without that primvar has none (the reader's fallback
    (0, 0) everywhere), even when it has an st (renderer/usd_shading.h's uvPrimvarOf)."""
    stage, path = new_stage(tmp_path)
    for name, varname in (("st", "st"), ("UVMap", "UVMap"), ("st", "uvSet9")):
        mesh = define_mesh(stage, f"/{name}For{varname}")
        st = UsdGeom.PrimvarsAPI(mesh).CreatePrimvar(name, Sdf.ValueTypeNames.TexCoord2fArray,
                                                     UsdGeom.Tokens.faceVarying)
        st.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
        st.SetIndices(Vt.IntArray([3, 2, 1, 0]))
        bind(mesh, add_textured_material(stage, "brick.png", path=f"/Looks/{varname}", varname=varname))
    load(stage, path, fake_scene)
    for name in ("st", "UVMap"):
        uvs = fake_scene.mesh(f"/{name}For{name}").uvs
        assert np.allclose(uvs, np.array([(0, 1), (1, 1), (1, 0), (0, 0)])[[0, 1, 2, 0, 2, 3]]), name
    assert fake_scene.mesh("/stForuvSet9").uvs is None


def test_left_handed_orientation_flips_the_winding(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    define_mesh(stage, "/Right")
    define_mesh(stage, "/Left").CreateOrientationAttr(UsdGeom.Tokens.leftHanded)
    load(stage, path, fake_scene)
    assert np.allclose(triangle_normals(fake_scene.mesh("/Right")), (0, 0, 1))
    assert np.allclose(triangle_normals(fake_scene.mesh("/Left")), (0, 0, -1))


def test_transform_double_sided_and_display_color(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    group = UsdGeom.Xform.Define(stage, "/Group")
    group.AddTranslateOp().Set(Gf.Vec3d(1, 2, 3))
    mesh = define_mesh(stage, "/Group/Quad")
    mesh.AddScaleOp().Set(Gf.Vec3f(2, 2, 2))
    mesh.CreateDoubleSidedAttr(False)
    mesh.CreateDisplayColorAttr([(0.2, 0.4, 0.6)])
    load(stage, path, fake_scene)
    recorded = fake_scene.mesh("/Group/Quad")
    assert np.allclose(recorded.transform, np.diag([2, 2, 2, 1]) + np.outer([0, 0, 0, 1], [1, 2, 3, 0]))
    assert not recorded.double_sided
    assert np.allclose(fake_scene.material_of("/Group/Quad").diffuse_color, (0.2, 0.4, 0.6))


def test_unbound_prims_inherit_display_color_or_get_the_preview_surface_defaults(tmp_path, fake_scene):
    """No material: a UsdPreviewSurface with the spec's defaults (0.18 diffuse, metallic workflow
    with the 1.5 IOR's Fresnel lobe), its diffuse the displayColor the prim has or inherits from a
    constant primvar of an ancestor (renderer/usd_shading.h, as hdGi does)."""
    stage, path = new_stage(tmp_path)
    group = UsdGeom.Xform.Define(stage, "/Painted")
    UsdGeom.PrimvarsAPI(group).CreatePrimvar("displayColor", Sdf.ValueTypeNames.Color3fArray,
                                             UsdGeom.Tokens.constant).Set([(0.2, 0.4, 0.6)])
    define_mesh(stage, "/Painted/Child")
    define_mesh(stage, "/Bare")
    load(stage, path, fake_scene)
    inherited, bare = fake_scene.material_of("/Painted/Child"), fake_scene.material_of("/Bare")
    assert np.allclose(inherited.diffuse_color, (0.2, 0.4, 0.6))
    assert np.allclose(bare.diffuse_color, (0.18, 0.18, 0.18))
    for material in (inherited, bare):
        assert not material.use_specular_workflow and material.ior == pytest.approx(1.5)
        assert material.roughness == pytest.approx(0.5) and material.metallic == 0


def test_invisible_and_guide_prims_are_skipped(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    UsdGeom.Xform.Define(stage, "/Hidden").CreateVisibilityAttr(UsdGeom.Tokens.invisible)
    define_mesh(stage, "/Hidden/Child")
    define_mesh(stage, "/Guide").CreatePurposeAttr(UsdGeom.Tokens.guide)
    define_mesh(stage, "/Proxy").CreatePurposeAttr(UsdGeom.Tokens.proxy)
    define_mesh(stage, "/Render").CreatePurposeAttr(UsdGeom.Tokens.render)
    define_mesh(stage, "/Shown")
    load(stage, path, fake_scene)
    assert sorted(m.name for m in fake_scene.meshes) == ["/Render", "/Shown"]


@pytest.mark.parametrize("axis", ["X", "Y", "Z"])
def test_implicit_prims_are_closed_outward_tessellations(tmp_path, fake_scene, axis):
    stage, path = new_stage(tmp_path)
    UsdGeom.Cube.Define(stage, "/Cube").CreateSizeAttr(2.0)
    for type_name in ("Cylinder", "Cone", "Capsule"):
        shape = getattr(UsdGeom, type_name).Define(stage, f"/{type_name}")
        shape.CreateRadiusAttr(0.5)
        shape.CreateHeightAttr(2.0)
        shape.CreateAxisAttr(axis)
    plane = UsdGeom.Plane.Define(stage, "/Plane")
    plane.CreateWidthAttr(2.0)
    plane.CreateLengthAttr(4.0)
    plane.CreateAxisAttr(axis)
    loaded = load(stage, path, fake_scene)
    assert loaded.warnings == []
    volumes = {"/Cube": 8.0, "/Cylinder": math.pi * 0.25 * 2, "/Cone": math.pi * 0.25 * 2 / 3,
               "/Capsule": math.pi * 0.25 * 2 + 4 / 3 * math.pi * 0.125}
    for name, volume in volumes.items():
        assert signed_volume(fake_scene.mesh(name)) == pytest.approx(volume, rel=0.02), name
    for name in ("/Cylinder", "/Cone", "/Capsule"):  # long along the axis
        extent = np.ptp(fake_scene.mesh(name).positions, axis=0)
        assert "XYZ"[int(np.argmax(extent))] == axis, name
    quad = fake_scene.mesh("/Plane")
    assert np.allclose(triangle_normals(quad), np.eye(3)["XYZ".index(axis)])
    assert sorted(np.ptp(quad.positions, axis=0)) == pytest.approx([0, 2, 4])


# -- instancing ----------------------------------------------------------------------------------

def test_point_instancer_adds_one_prototype_and_an_instance_each(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    instancer = UsdGeom.PointInstancer.Define(stage, "/Instancer")
    instancer.AddTranslateOp().Set(Gf.Vec3d(0, 10, 0))
    define_mesh(stage, "/Instancer/Prototypes/Tile")
    instancer.CreatePrototypesRel().SetTargets(["/Instancer/Prototypes/Tile"])
    instancer.CreateProtoIndicesAttr([0, 0, 0])
    instancer.CreatePositionsAttr([(0, 0, 0), (3, 0, 0), (6, 0, 0)])
    loaded = load(stage, path, fake_scene)
    assert fake_scene.prototypes == ["/Instancer/Prototypes/Tile"]
    assert len(fake_scene.meshes) == 1 and fake_scene.meshes[0].prototype == 0
    assert len(fake_scene.instances) == 3 and {i.prototype for i in fake_scene.instances} == {0}
    translations = [tuple(np.asarray(i.transform)[3, :3]) for i in fake_scene.instances]
    assert np.allclose(translations, [(0, 10, 0), (3, 10, 0), (6, 10, 0)])
    assert [i.name for i in fake_scene.instances] == [f"/Instancer[{k}]" for k in range(3)]
    assert loaded.counts["instances"] == 3 and loaded.counts["prototypes"] == 1


def test_point_instances_are_named_by_zero_padded_index(tmp_path, fake_scene):
    """Names sort as the points do (the renderer orders emissive instances by name; hdGi pads
    Hydra's instance index the same way): 12 points are [00] ... [11]."""
    stage, path = new_stage(tmp_path)
    instancer = UsdGeom.PointInstancer.Define(stage, "/Instancer")
    define_mesh(stage, "/Instancer/Prototypes/Tile")
    instancer.CreatePrototypesRel().SetTargets(["/Instancer/Prototypes/Tile"])
    instancer.CreateProtoIndicesAttr([0] * 12)
    instancer.CreatePositionsAttr([(3 * k, 0, 0) for k in range(12)])
    load(stage, path, fake_scene)
    names = [i.name for i in fake_scene.instances]
    assert names == [f"/Instancer[{k:02d}]" for k in range(12)] and names == sorted(names)


def test_point_instancer_honours_invisible_ids_and_bad_proto_indices(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    instancer = UsdGeom.PointInstancer.Define(stage, "/Instancer")
    UsdGeom.Sphere.Define(stage, "/Instancer/Ball").AddTranslateOp().Set(Gf.Vec3d(0, 0, 1))
    instancer.CreatePrototypesRel().SetTargets(["/Instancer/Ball"])
    instancer.CreateProtoIndicesAttr([0, 0, 5, 0])
    instancer.CreatePositionsAttr([(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)])
    instancer.CreateInvisibleIdsAttr([1])
    loaded = load(stage, path, fake_scene)
    assert [i.name for i in fake_scene.instances] == ["/Instancer[0]", "/Instancer[3]"]
    # The prototype root's own transform comes first, as UsdGeomPointInstancer specifies.
    assert np.allclose([np.asarray(i.transform)[3, :3] for i in fake_scene.instances], [(0, 0, 1), (3, 0, 1)])
    assert np.allclose(fake_scene.spheres[0].transform, np.eye(4))
    assert len(fake_scene.spheres) == 1 and fake_scene.spheres[0].prototype == 0
    assert any("/Instancer" in w and "prototype 5" in w for w in loaded.warnings)


def test_instanceable_prims_share_one_prototype(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    define_mesh(stage, "/Library/Tile")
    stage.GetPrimAtPath("/Library").SetSpecifier(Sdf.SpecifierClass)  # not rendered itself
    for k in range(2):
        instance = UsdGeom.Xform.Define(stage, f"/Tile{k}")
        instance.GetPrim().GetReferences().AddInternalReference("/Library")
        instance.GetPrim().SetInstanceable(True)
        instance.AddTranslateOp().Set(Gf.Vec3d(5 * k, 0, 0))
    loaded = load(stage, path, fake_scene)
    assert len(fake_scene.prototypes) == 1 and len(fake_scene.meshes) == 1
    assert fake_scene.meshes[0].prototype == 0
    assert [i.name for i in fake_scene.instances] == ["/Tile0", "/Tile1"]
    assert np.allclose([np.asarray(i.transform)[3, 0] for i in fake_scene.instances], [0, 5])
    assert loaded.counts["meshes"] == 1 and loaded.counts["instances"] == 2


# -- materials -----------------------------------------------------------------------------------

def add_textured_material(stage, file, diffuse_constant=None, path="/Looks/Brick", varname="uvSet1"):
    material, surface = define_preview_material(stage, path)
    texture = UsdShade.Shader.Define(stage, f"{path}/Texture")
    texture.CreateIdAttr("UsdUVTexture")
    texture.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(file)
    texture.CreateInput("wrapS", Sdf.ValueTypeNames.Token).Set("clamp")
    texture.CreateInput("scale", Sdf.ValueTypeNames.Float4).Set(Gf.Vec4f(2, 2, 2, 1))
    texture.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set("sRGB")
    texture.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
    texture.CreateOutput("r", Sdf.ValueTypeNames.Float)
    reader = UsdShade.Shader.Define(stage, f"{path}/Reader")
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    reader.CreateInput("varname", Sdf.ValueTypeNames.Token).Set(varname)
    reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    transform = UsdShade.Shader.Define(stage, f"{path}/Transform")
    transform.CreateIdAttr("UsdTransform2d")
    transform.CreateInput("in", Sdf.ValueTypeNames.Float2).ConnectToSource(reader.ConnectableAPI(), "result")
    transform.CreateInput("rotation", Sdf.ValueTypeNames.Float).Set(30)
    transform.CreateInput("scale", Sdf.ValueTypeNames.Float2).Set(Gf.Vec2f(4, 2))
    transform.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    texture.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(transform.ConnectableAPI(), "result")
    diffuse = surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f)
    if diffuse_constant is not None:
        diffuse.Set(diffuse_constant)
    diffuse.ConnectToSource(texture.ConnectableAPI(), "rgb")
    surface.CreateInput("roughness", Sdf.ValueTypeNames.Float).ConnectToSource(texture.ConnectableAPI(), "r")
    return material


def textured_quad(tmp_path, file, diffuse_constant=None):
    stage, path = new_stage(tmp_path)
    mesh = define_mesh(stage, "/Quad")
    for name, values in (("st", [(0, 0), (1, 0), (1, 1), (0, 1)]), ("uvSet1", [(0, 0), (2, 0), (2, 2), (0, 2)])):
        UsdGeom.PrimvarsAPI(mesh).CreatePrimvar(name, Sdf.ValueTypeNames.TexCoord2fArray,
                                                UsdGeom.Tokens.vertex).Set(values)
    bind(mesh, add_textured_material(stage, file, diffuse_constant))
    return stage, path


def test_texture_network_is_read_into_texture_descs(tmp_path, fake_scene):
    (tmp_path / "brick.png").write_bytes(b"not really a png; the loader only checks it exists")
    stage, path = textured_quad(tmp_path, "./brick.png")
    loaded = load(stage, path, fake_scene)
    assert loaded.warnings == []
    material = fake_scene.material_of("/Quad")
    diffuse, roughness = material.diffuse_color_texture, material.roughness_texture
    assert diffuse.file == str(tmp_path / "brick.png") and roughness.file == diffuse.file
    assert (diffuse.channel, roughness.channel) == ("rgb", "r")
    assert diffuse.wrap_s == "clamp" and diffuse.wrap_t == "useMetadata"
    assert np.allclose(diffuse.scale, (2, 2, 2, 1)) and diffuse.source_color_space == "sRGB"
    assert diffuse.st_rotation == 30 and np.allclose(diffuse.st_scale, (4, 2))
    assert material.opacity_texture.file == ""
    # The reader's varname picks the uv set, not the conventional "st".
    assert np.allclose(fake_scene.mesh("/Quad").uvs, [(0, 0), (2, 0), (2, 2), (0, 2)])
    assert loaded.textures == {"./brick.png": str(tmp_path / "brick.png")}


def test_missing_texture_warns_naming_material_and_file_and_reads_its_fallback(tmp_path, fake_scene):
    """The input's own value (0.3, 0.2, 0.1) is overridden by its connection: a missing file reads
    the texture's fallback, here the spec's (0, 0, 0, 1), in the channel each input takes."""
    stage, path = textured_quad(tmp_path, "missing_brick.png", diffuse_constant=(0.3, 0.2, 0.1))
    loaded = load(stage, path, fake_scene)
    warnings = [w for w in loaded.warnings if "missing_brick.png" in w]
    assert len(warnings) == 1 and "/Looks/Brick" in warnings[0] and str(path) in warnings[0]
    material = fake_scene.material_of("/Quad")
    assert material.diffuse_color_texture.file == ""
    assert np.allclose(material.diffuse_color, (0, 0, 0)) and material.roughness == 0
    assert loaded.textures == {"missing_brick.png": None}


def test_shader_networks_cross_the_bindings_typed():
    """gi._core.ShaderNode takes what UsdShade gives (numbers, 2 to 4 numbers, str, assets) as
    renderer/shader_network.h holds it, so the resolver reads the loader's networks as hdGi's; any
    other value is a TypeError naming its type, not a silent default."""
    _core = pytest.importorskip("gi._core")
    surface, texture = _core.ShaderNode("UsdPreviewSurface"), _core.ShaderNode("UsdUVTexture")
    surface.set("diffuseColor", (0.1, 0.2, 0.3))
    surface.set("useSpecularWorkflow", True)
    surface.set("roughness", 1)
    surface.connect("metallic", "/M/Tex", "g")
    texture.set("file", _core.ShaderAsset("./gone.png", ""))
    texture.set("fallback", [0.0, 0.25, 0.0, 1.0])
    network = _core.ShaderNetwork()
    network.add("/M/Surface", surface)
    network.add("/M/Tex", texture)
    warnings = []
    desc, varnames, files = _core.resolve_preview_surface("/M", network, "/M/Surface",
                                                          lambda path, message: warnings.append((path, message)))
    assert np.allclose(desc.diffuse_color, (0.1, 0.2, 0.3)) and desc.use_specular_workflow
    assert desc.roughness == 1 and desc.metallic == 0.25  # the missing texture's fallback, channel g
    assert varnames == [] and files == [("./gone.png", "")]
    assert len(warnings) == 1 and warnings[0][0] == "/M" and "'./gone.png'" in warnings[0][1]
    with pytest.raises(TypeError, match="dict"):
        surface.set("ior", {"not": "a value"})
    with pytest.raises(TypeError):
        surface.set("ior", (1.0, 2.0, 3.0, 4.0, 5.0))


def test_each_material_is_added_once(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    red = (Sdf.ValueTypeNames.Color3f, (1, 0, 0))
    material, _ = define_preview_material(stage, "/Looks/Red", diffuseColor=red)
    for k in range(3):
        bind(define_mesh(stage, f"/Quad{k}"), material)
    loaded = load(stage, path, fake_scene)
    assert len(fake_scene.materials) == 1 and loaded.counts["materials"] == 1
    assert {m.material for m in fake_scene.meshes} == {0}


# -- lights and cameras --------------------------------------------------------------------------

def test_every_light_kind(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    UsdLux.DiskLight.Define(stage, "/Disk").CreateRadiusAttr(0.25)
    sphere = UsdLux.SphereLight.Define(stage, "/Sphere")
    sphere.CreateRadiusAttr(0.1)
    sphere.CreateColorAttr(Gf.Vec3f(1, 0.5, 0.25))
    sphere.CreateExposureAttr(2)
    sphere.CreateNormalizeAttr(True)
    cylinder = UsdLux.CylinderLight.Define(stage, "/Cylinder")
    cylinder.CreateLengthAttr(3)
    cylinder.CreateRadiusAttr(0.05)
    UsdLux.DistantLight.Define(stage, "/Sun").CreateAngleAttr(1.5)
    (tmp_path / "sky.exr").write_bytes(b"stand-in")
    UsdLux.DomeLight.Define(stage, "/Sky").CreateTextureFileAttr("sky.exr")
    UsdLux.RectLight.Define(stage, "/Hidden").CreateVisibilityAttr(UsdGeom.Tokens.invisible)
    loaded = load(stage, path, fake_scene)
    lights = {light.name: light for light in fake_scene.lights}
    assert {name: light.kind for name, light in lights.items()} == {
        "/Disk": "disk", "/Sphere": "sphere", "/Cylinder": "cylinder", "/Sun": "distant", "/Sky": "dome"}
    assert lights["/Disk"].radius == pytest.approx(0.25)
    assert np.allclose(lights["/Sphere"].color, (1, 0.5, 0.25)) and lights["/Sphere"].exposure == 2
    assert lights["/Sphere"].normalize and lights["/Sphere"].radius == pytest.approx(0.1)
    assert lights["/Cylinder"].length == 3 and lights["/Cylinder"].radius == pytest.approx(0.05)
    assert lights["/Sun"].angle == pytest.approx(1.5)
    assert lights["/Sky"].texture_file == str(tmp_path / "sky.exr")
    assert loaded.light_kinds == {"disk": 1, "sphere": 1, "cylinder": 1, "distant": 1, "dome": 1}


def test_camera_argument_and_missing_camera(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    UsdGeom.Camera.Define(stage, "/Other").CreateFocalLengthAttr(35)
    loaded = load(stage, path, fake_scene, camera="/Other")
    assert loaded.camera_path == "/Other" and fake_scene.cameras[-1].focal_length == 35
    with pytest.raises(SceneError, match="/Nope"):
        load_stage(path, scene=fake_scene, camera="/Nope")


def test_no_camera_frames_the_scene_from_plus_z(tmp_path, fake_scene):
    path = tmp_path / "nocamera.usda"
    stage = Usd.Stage.CreateNew(str(path))
    define_mesh(stage, "/Quad", [(x + 10, y, 0) for x, y, _ in QUAD])
    loaded = load(stage, path, fake_scene)
    assert loaded.camera_path == "" and any("no camera" in w for w in loaded.warnings)
    position = np.asarray(fake_scene.cameras[0].transform)[3, :3]
    assert position[0] == pytest.approx(10) and position[1] == pytest.approx(0) and position[2] > 1


# -- bad input -----------------------------------------------------------------------------------

def test_missing_file_raises_scene_error_naming_it(tmp_path, fake_scene):
    with pytest.raises(SceneError, match="nope.usda"):
        load_stage(tmp_path / "nope.usda", scene=fake_scene)


@pytest.mark.parametrize("name", ["bad.usda", "bad.txt"])
def test_non_usd_file_raises_scene_error_naming_it(tmp_path, fake_scene, name):
    (tmp_path / name).write_text("this is not USD\n")
    with pytest.raises(SceneError, match=name.replace(".", r"\.")):
        load_stage(tmp_path / name, scene=fake_scene)


def test_out_of_range_indices_and_nan_points_warn_and_drop_faces(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (math.nan, 0, 0), (math.inf, 1, 1)]
    define_mesh(stage, "/World/Broken", points, counts=[3, 3, 3, 3], indices=[0, 1, 2, 0, 1, 7, 0, 3, 1, 2, -1, 0])
    loaded = load(stage, path, fake_scene)
    warnings = [w for w in loaded.warnings if "/World/Broken" in w]
    assert all(w.startswith(str(path)) for w in warnings)
    assert any("out-of-range" in w for w in warnings) and any("NaN" in w for w in warnings)
    mesh = fake_scene.mesh("/World/Broken")
    assert len(mesh.indices) == 1 and np.isfinite(mesh.positions).all() and len(mesh.positions) == 3


def test_counts_that_do_not_sum_warn_and_drop_the_faces_past_the_end(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    define_mesh(stage, "/Short", counts=[3, 3], indices=[0, 1, 2, 0])
    define_mesh(stage, "/Empty", counts=[4], indices=[0, 1, 9, 3])
    loaded = load(stage, path, fake_scene)
    assert any("/Short" in w and "faceVertexCounts sum to 6" in w for w in loaded.warnings)
    assert len(fake_scene.mesh("/Short").indices) == 1
    assert [m.name for m in fake_scene.meshes] == ["/Short"]  # nothing of /Empty is usable
    assert any("/Empty" in w and "no valid faces" in w for w in loaded.warnings)


def test_bad_primvars_are_ignored_with_a_warning(tmp_path, fake_scene):
    stage, path = new_stage(tmp_path)
    mesh = define_mesh(stage, "/Quad")
    mesh.CreateNormalsAttr([(0, 0, 1)] * 2)  # too few for vertex interpolation
    mesh.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    loaded = load(stage, path, fake_scene)
    assert fake_scene.mesh("/Quad").normals is None
    assert any("/Quad" in w and "normals" in w for w in loaded.warnings)


# -- without the compiled core -------------------------------------------------------------------

def test_loader_runs_without_the_compiled_core():
    """Blocks gi._core in a fresh interpreter: the loader falls back to pure-Python descriptors."""
    script = (
        "import sys; sys.modules['gi._core'] = None\n"
        f"sys.path.insert(0, {str(SOURCE)!r})\n"
        "from gi.descriptors import HAVE_CORE, CountingScene\n"
        "from gi.loader import load_stage\n"
        f"loaded = load_stage({str(CORNELL)!r}, scene=CountingScene())\n"
        "assert not HAVE_CORE\n"
        "print(loaded.counts['meshes'], loaded.counts['spheres'], loaded.counts['lights'])\n")
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["5", "1", "1"]


def test_camera_defaults_are_the_schemas_in_both_descriptors():
    """The compiled CameraDesc's defaults (renderer/camera_desc.h, written once for both hosts) and
    the pure-Python stand-in's (read from the schema) are UsdGeomCamera's fallbacks."""
    pytest.importorskip("gi._core")
    from gi import _core, descriptors
    core, stand_in = _core.CameraDesc(), descriptors.PYTHON_DESCRIPTORS["CameraDesc"]()
    assert core.projection == stand_in.projection
    for name in ("focal_length", "horizontal_aperture", "vertical_aperture", "horizontal_aperture_offset",
                 "vertical_aperture_offset", "f_stop", "focus_distance"):
        assert getattr(core, name) == pytest.approx(getattr(stand_in, name), rel=1e-7), name


def test_preview_surface_defaults_are_the_specs_in_both_descriptors():
    """The compiled MaterialDesc's and TextureDesc's defaults (renderer/material.h, texture.h: the
    only place either host takes UsdPreviewSurface's defaults from) equal the pure-Python
    stand-ins', which read them from the shaders' Sdr definitions: the spec's."""
    pytest.importorskip("gi._core")
    from gi import _core, descriptors
    for core, stand_in in ((_core.MaterialDesc(), descriptors.PYTHON_DESCRIPTORS["MaterialDesc"]()),
                           (_core.TextureDesc(), descriptors.PYTHON_DESCRIPTORS["TextureDesc"]())):
        for name, expected in vars(stand_in).items():
            value = getattr(core, name)
            if isinstance(expected, (str, bool)):
                assert value == expected, name
            elif not hasattr(expected, "file"):  # a nested TextureDesc is checked on its own
                assert np.allclose(value, expected, rtol=1e-7, atol=0), name


# -- the command line's generated flags (no core needed) -----------------------------------------

CATALOG = [
    {"name": "path", "description": "", "params": [
        {"name": "pathDepth", "type": "int", "default": 5, "min": 0, "max": 1024, "description": "depth"},
        {"name": "useMis", "type": "bool", "default": True, "min": False, "max": True, "description": "MIS"}]},
    {"name": "photons", "description": "", "params": [
        {"name": "photonRadius", "type": "float", "default": 0.1, "min": 0.0, "max": 10.0, "description": "r"}]},
]


def flag_parser():
    import argparse
    from gi.cli import IntegratorFlags
    flags = IntegratorFlags(CATALOG)
    parser = argparse.ArgumentParser()
    parser.add_argument("--integrator", default="path")
    flags.add_to(parser)
    return parser, flags


def test_integrator_flags_are_generated_from_the_catalog(capsys):
    from gi.cli import kebab
    assert kebab("pathDepth") == "path-depth" and kebab("photonRadius") == "photon-radius"
    parser, flags = flag_parser()
    args = parser.parse_args(["--path-depth", "7", "--no-use-mis"])
    assert flags.chosen(args, parser) == {"pathDepth": 7, "useMis": False}
    # A flag the chosen integrator does not take is a usage error naming it.
    with pytest.raises(SystemExit):
        flags.chosen(parser.parse_args(["--path-depth", "7", "--photon-radius", "0.5"]), parser)
    assert "--photon-radius is not a parameter of 'path'" in capsys.readouterr().err
    args = parser.parse_args(["--integrator", "photons", "--photon-radius", "0.5"])
    assert flags.chosen(args, parser) == {"photonRadius": 0.5}
    assert "depth (0..1024; default 5; path)" in parser.format_help().replace("\n", " ").replace("  ", " ")


def test_integrator_flag_out_of_range_is_a_usage_error():
    parser, flags = flag_parser()
    with pytest.raises(SystemExit):
        flags.chosen(parser.parse_args(["--path-depth", "5000"]), parser)


def purposes_stage(tmp_path, included=None):
    """A sphere of each purpose (default, render, proxy, guide) under one parent; `included`: the
    render settings' includedPurposes, if authored."""
    from pxr import UsdRender
    stage, path = new_stage(tmp_path)
    for purpose in ("default", "render", "proxy", "guide"):
        UsdGeom.Sphere.Define(stage, f"/Geo/{purpose}").CreatePurposeAttr(purpose)
    settings = UsdRender.Settings.Define(stage, "/Render/Settings")
    if included is not None:
        settings.CreateIncludedPurposesAttr(included)
    stage.SetMetadata("renderSettingsPrimPath", "/Render/Settings")
    stage.Save()
    return path


@pytest.mark.parametrize("included, requested, expected", [
    (None, None, {"default", "render"}),                # includedPurposes' fallback
    (["default", "proxy"], None, {"default", "proxy"}),  # the render settings say
    (["proxy"], None, {"default", "proxy"}),             # default is always rendered
    (["default", "proxy"], ["guide"], {"default", "guide"}),  # --purposes wins, as usdrecord's flag
    (None, ["proxy", "render"], {"default", "proxy", "render"}),
])
def test_purposes_rendered(tmp_path, fake_scene, included, requested, expected):
    path = purposes_stage(tmp_path, included)
    load_stage(str(path), fake_scene, purposes=requested)
    assert {s.name.rsplit("/", 1)[-1] for s in fake_scene.spheres} == expected


def test_an_unknown_purpose_warns_naming_where_it_was_given(tmp_path, fake_scene):
    path = purposes_stage(tmp_path, ["default", "proxie"])
    loaded = load_stage(str(path), fake_scene)
    assert any("/Render/Settings" in w and "'proxie'" in w for w in loaded.warnings), loaded.warnings
    assert {s.name.rsplit("/", 1)[-1] for s in fake_scene.spheres} == {"default"}
    loaded = load_stage(str(path), type(fake_scene)(), purposes=["prox"])
    assert any("--purposes" in w and "'prox'" in w for w in loaded.warnings), loaded.warnings


def test_gi_render_takes_usdrecords_purposes_flag(tmp_path):
    from conftest import run_gi
    path = purposes_stage(tmp_path)
    proc = run_gi("render", path, "--purposes", "proxy,guide", "--spp", 1, "--resolution", 8, 8,
                  "-o", tmp_path / "out.exr", "--no-png")
    assert proc.returncode == 0
