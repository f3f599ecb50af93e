"""Bad input gets a clear message naming the file and prim; nothing crashes."""
import math

from pxr import Gf, Sdf, Usd, UsdGeom, UsdShade

from conftest import run_gi


def _stage(tmp_path, name="scene.usda"):
    path = tmp_path / name
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.Camera.Define(stage, "/Cam").AddTranslateOp().Set(Gf.Vec3d(0, 0, 5))
    return stage, path


def _render(path, tmp_path):
    return run_gi("render", path, "--spp", 1, "--resolution", 8, 8, "-o", tmp_path / "o.exr", "--no-png", check=False)


def test_missing_file(tmp_path):
    proc = _render(tmp_path / "nope.usda", tmp_path)
    assert proc.returncode == 2
    assert "nope.usda: no such file" in proc.stderr and "Traceback" not in proc.stderr


def test_not_a_usd_file(tmp_path):
    bad = tmp_path / "bad.usda"
    bad.write_text("this is not USD\n")
    proc = _render(bad, tmp_path)
    assert proc.returncode == 2
    assert "bad.usda: not a readable USD file" in proc.stderr and "Traceback" not in proc.stderr


def test_out_of_range_indices_and_nan_points(tmp_path):
    stage, path = _stage(tmp_path)
    mesh = UsdGeom.Mesh.Define(stage, "/World/Broken")
    mesh.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0), (math.nan, 0, 0)])
    mesh.CreateFaceVertexCountsAttr([3, 3, 3])
    mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 0, 1, 7, 0, 3, 1])
    stage.Save()
    proc = _render(path, tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "/World/Broken" in proc.stderr and "out-of-range" in proc.stderr
    assert "NaN" in proc.stderr


def test_missing_texture_names_material_and_file(tmp_path):
    stage, path = _stage(tmp_path)
    mesh = UsdGeom.Mesh.Define(stage, "/World/Quad")
    mesh.CreatePointsAttr([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)])
    mesh.CreateFaceVertexCountsAttr([4])
    mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    material = UsdShade.Material.Define(stage, "/World/Looks/Brick")
    surface = UsdShade.Shader.Define(stage, "/World/Looks/Brick/Surface")
    surface.CreateIdAttr("UsdPreviewSurface")
    texture = UsdShade.Shader.Define(stage, "/World/Looks/Brick/Texture")
    texture.CreateIdAttr("UsdUVTexture")
    texture.CreateInput("file", Sdf.ValueTypeNames.Asset).Set("missing_brick.png")
    texture.CreateOutput("rgb", Sdf.ValueTypeNames.Float3)
    surface.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(texture.ConnectableAPI(), "rgb")
    material.CreateSurfaceOutput().ConnectToSource(surface.ConnectableAPI(), "surface")
    UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(material)
    stage.Save()
    proc = _render(path, tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "/World/Looks/Brick" in proc.stderr and "missing_brick.png" in proc.stderr


def test_unknown_integrator_is_a_usage_error(cornell, tmp_path):
    proc = run_gi("render", cornell, "--integrator", "magic", check=False)
    assert proc.returncode == 2 and "invalid choice: 'magic'" in proc.stderr


def _stage_with_missing_layers(tmp_path):
    """A lit plane, plus a sublayer, a reference and a payload that do not exist."""
    stage, path = _stage(tmp_path)
    stage.GetRootLayer().subLayerPaths.append("./missing_sublayer.usda")
    plane = UsdGeom.Mesh.Define(stage, "/Plane")
    plane.CreatePointsAttr([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)])
    plane.CreateFaceVertexCountsAttr([4])
    plane.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    stage.DefinePrim("/Props").GetReferences().AddReference("./missing_reference.usda")
    stage.DefinePrim("/Set").GetPayloads().AddPayload("./missing_payload.usda")
    from pxr import UsdLux
    UsdLux.DomeLight.Define(stage, "/Sky")
    stage.Save()
    return path


def test_missing_sublayers_references_and_payloads_are_an_error_naming_them(tmp_path):
    path = _stage_with_missing_layers(tmp_path)
    proc = _render(path, tmp_path)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "3 layer(s) or prim(s) it names cannot be found" in proc.stderr, proc.stderr
    for name in ("missing_sublayer.usda", "missing_reference.usda", "missing_payload.usda"):
        assert name in proc.stderr
    assert "--allow-missing" in proc.stderr
    assert not (tmp_path / "o.exr").exists()


def test_allow_missing_renders_and_warns_for_each(tmp_path):
    path = _stage_with_missing_layers(tmp_path)
    proc = run_gi("render", path, "--spp", 1, "--resolution", 8, 8, "-o", tmp_path / "o.exr", "--no-png",
                  "--allow-missing")
    assert proc.returncode == 0, proc.stderr
    warnings = [line for line in proc.stderr.splitlines() if "not found, rendered without it" in line]
    assert len(warnings) == 3 and all(str(path) in line for line in warnings), proc.stderr
    assert (tmp_path / "o.exr").exists()


def test_render_settings_relationships_authored_as_attributes_warn_and_render(tmp_path):
    """Found by the fuzzer: a RenderSettings whose `camera` (or a product's `orderedVars`) is authored
    as an attribute, which pxr refuses to compose as a relationship, warns naming the property and
    renders with what is left (the first camera; no product) instead of a traceback."""
    scene = tmp_path / "scene.usda"
    scene.write_text(RELATIONSHIPS_AS_ATTRIBUTES.replace("PRODUCT_PATH", str(tmp_path / "product.exr")))
    proc = run_gi("render", scene, "--spp", 1, "--resolution", 8, 8, "-o", tmp_path / "o.exr", "--no-png", check=False)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    assert "/Render/Settings.camera: could not be read as a relationship" in proc.stderr, proc.stderr
    proc = run_gi("render", scene, "--spp", 1, "--no-png", check=False, cwd=tmp_path)  # reads the products
    assert proc.returncode == 0, proc.stderr
    assert "/Render/Product.orderedVars: could not be read as a relationship" in proc.stderr, proc.stderr


RELATIONSHIPS_AS_ATTRIBUTES = """#usda 1.0
(
    renderSettingsPrimPath = "/Render/Settings"
)

def Camera "Cam"
{
    double3 xformOp:translate = (0, 0, 5)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}

def Sphere "Ball"
{
}

def DistantLight "Sun"
{
}

def Scope "Render"
{
    def RenderSettings "Settings"
    {
        custom string camera = "/Cam"
        rel products = </Render/Product>
        uniform int2 resolution = (8, 8)
    }

    def RenderProduct "Product"
    {
        custom string orderedVars = "/Render/Vars/Color"
        token productName = "PRODUCT_PATH"
    }
}
"""
