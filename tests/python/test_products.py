"""UsdRender products and vars: without -o, `gi render` writes each RenderProduct of the render
settings with its name, resolution, camera, data window and RenderVars as typed EXR channels;
bad products and vars warn naming the prim and the rest is written."""
import numpy as np

from conftest import new_stage, run_gi


def product_stage(tmp_path):
    """Two cameras, a ball and a light; render settings with two products:
    beauty.$F4.exr: 24x16 from /Camera with color, depth, normal, primId and two bad vars;
    side.####.exr: 12x10 from /Side (its own camera), the left half (dataWindowNDC), half-float color;
    plus a product whose camera does not exist."""
    from pxr import Gf, Sdf, UsdGeom, UsdLux, UsdRender
    stage, path = new_stage(tmp_path)
    UsdGeom.Camera.Define(stage, "/Side").AddTranslateOp().Set(Gf.Vec3d(1, 0, 6))
    UsdGeom.Sphere.Define(stage, "/Ball")
    UsdLux.SphereLight.Define(stage, "/Light").AddTranslateOp().Set(Gf.Vec3d(0, 3, 3))

    def var(name, source, data_type):
        v = UsdRender.Var.Define(stage, f"/Render/Vars/{name}")
        v.CreateSourceNameAttr(source)
        v.CreateDataTypeAttr(data_type)
        return v.GetPath()

    settings = UsdRender.Settings.Define(stage, "/Render/Settings")
    settings.CreateResolutionAttr(Gf.Vec2i(24, 16))
    settings.GetCameraRel().AddTarget("/Camera")
    stage.SetMetadata("renderSettingsPrimPath", "/Render/Settings")

    beauty = UsdRender.Product.Define(stage, "/Render/Beauty")
    beauty.CreateProductNameAttr(str(tmp_path / "beauty.$F4.exr"))
    for target in (var("color", "color", "color3f"), var("depth", "depth", "float"),
                   var("N", "normal", "normal3f"), var("id", "primId", "int"),
                   var("motion", "motionVector", "vector3f"), var("weird", "albedo", "quaternion")):
        beauty.GetOrderedVarsRel().AddTarget(target)

    side = UsdRender.Product.Define(stage, "/Render/Side")
    side.CreateProductNameAttr(str(tmp_path / "side.####.exr"))
    side.CreateResolutionAttr(Gf.Vec2i(12, 10))
    side.GetCameraRel().AddTarget("/Side")
    side.CreateDataWindowNDCAttr(Gf.Vec4f(0, 0, 0.5, 1))
    side.GetOrderedVarsRel().AddTarget(var("halfColor", "color", "color3h"))

    lost = UsdRender.Product.Define(stage, "/Render/Lost")
    lost.CreateProductNameAttr(str(tmp_path / "lost.exr"))
    lost.GetCameraRel().AddTarget("/NoSuchCamera")
    lost.GetOrderedVarsRel().AddTarget(Sdf.Path("/Render/Vars/color"))

    for product in (beauty, side, lost):
        settings.GetProductsRel().AddTarget(product.GetPath())
    stage.Save()
    return path


def read(path):
    from gi import _core
    return _core.read_image(str(path))


def test_products_are_written_with_their_vars_resolution_camera_and_window(tmp_path):
    scene = product_stage(tmp_path)
    proc = run_gi("render", scene, "--frames", "1", "--spp", 2, "--seed", 4)
    # Beauty: the declared vars as named channels, bad vars skipped with a warning naming them.
    pixels, meta = read(tmp_path / "beauty.0001.exr")
    assert pixels.shape[:2] == (16, 24)
    assert sorted(meta["channels"]) == sorted(["R", "G", "B", "depth", "N.X", "N.Y", "N.Z", "id"])
    assert meta["gi:product"] == "/Render/Beauty"
    assert "/Render/Vars/motion: sourceName 'motionVector' is not an output" in proc.stderr
    assert "/Render/Vars/weird: dataType 'quaternion' is not one this renderer writes" in proc.stderr
    # The same frame through -o: the product's colour and depth are its pixels.
    run_gi("render", scene, "--frames", "1", "--spp", 2, "--seed", 4, "--resolution", 24, 16,
           "-o", tmp_path / "plain.exr", "--no-png")
    plain, plain_meta = read(tmp_path / "plain.exr")
    channel = {name: i for i, name in enumerate(meta["channels"])}
    plain_channel = {name: i for i, name in enumerate(plain_meta["channels"])}
    for ours, theirs in (("R", "R"), ("B", "B"), ("depth", "Z"), ("N.Y", "N.Y")):
        assert np.array_equal(pixels[..., channel[ours]], plain[..., plain_channel[theirs]]), ours
    ids = pixels[..., channel["id"]]
    assert set(np.unique(ids)) <= {-1.0, 0.0} and (ids == 0).any() and (ids == -1).any()  # the ball, nothing
    # Side: its own resolution and camera, the left half as the data window, half-float colour.
    side, side_meta = read(tmp_path / "side.0001.exr")
    assert side_meta["data_window"] == (0, 0, 6, 10) and side_meta["display_window"] == (12, 10)
    assert side_meta["gi:camera"] == "/Side"
    assert side_meta["channel_formats"] == ["half"] * 3
    run_gi("render", scene, "--frames", "1", "--spp", 2, "--seed", 4, "--resolution", 12, 10, "--camera", "/Side",
           "-o", tmp_path / "side_plain.exr", "--no-png")
    side_plain, _ = read(tmp_path / "side_plain.exr")
    # The same pixels through /Side, rounded to half as the file stores them (both round to nearest even).
    assert np.array_equal(side, side_plain[:, :6, :3].astype(np.float16).astype(np.float32))
    # A camera that is not there: warned, rendered through the settings' camera.
    assert "/Render/Lost: camera /NoSuchCamera does not exist" in proc.stderr
    assert (tmp_path / "lost.exr").exists()


def test_output_flag_overrides_the_products(tmp_path):
    scene = product_stage(tmp_path)
    run_gi("render", scene, "--spp", 1, "-o", tmp_path / "only.exr", "--no-png")
    assert (tmp_path / "only.exr").exists() and not (tmp_path / "beauty.0000.exr").exists()


def test_a_settings_flag_that_names_no_render_settings_is_an_error(tmp_path):
    scene = product_stage(tmp_path)
    proc = run_gi("render", scene, "--settings", "/Render/Beauty", check=False)
    assert proc.returncode == 2 and "--settings /Render/Beauty is not a RenderSettings prim" in proc.stderr
