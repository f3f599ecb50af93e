"""Motion blur: the camera's shutter gives each camera ray a time; moving spheres, meshes (moved or
deformed) and instances become Embree motion geometry, moving area lights move with each ray's
time (renderer/moving_light.h); nothing moving renders bit-identically with and without a shutter
interval; a shutter closing before it opens is warned about.

The scenes: an orthographic camera 8 x 2 units wide (128 x 32 pixels, 16 pixels a unit) over a
uniform dome of radiance 1, and a black object moving along x by TRAVEL during the shutter (frame 1,
shutter -0.25..0.25). A pixel's value is 1 minus the share of its samples that hit the object, so
the column means of 1 - image are the object's coverage profile along x, blurred by the motion. A
moving light (radiance 1) is seen against black instead: the column means of the image are its
profile."""
import numpy as np
import pytest

from gi.descriptors import HAVE_CORE

needs_core = pytest.mark.skipif(not HAVE_CORE, reason="needs gi._core")

PIXELS_PER_UNIT = 16
RESOLUTION = (128, 32)
TRAVEL = 2.0          # units the object moves while the shutter is open (32 pixels)
SIZE = 1.0            # the sphere's diameter, the quad's width (16 pixels)
SHUTTER = (-0.25, 0.25)
FRAME = 1
SPP = 64
LIGHT_KINDS = ("sphere light", "rect light")


def motion_stage(path, kind, shutter=SHUTTER, travel=TRAVEL, albedo=0.0, backdrop=False):
    """Writes the scene (see the module's docstring) with a `kind` of moving object: 'sphere'
    (translated), 'quad' (translated mesh), 'deforming quad' (its points time-sampled), 'instance'
    (an instanceable prim holding the quad, translated) or 'point instancer' (one instance of the
    quad, at x = 0 on FRAME with a velocity: USD extrapolates it over the shutter); 'camera': the
    sphere stands still and the camera moves the other way; 'sphere light' and 'rect light' (the
    quad's size, facing the camera), translated, without the dome. `backdrop`: a still grey quad
    behind, which the light lights."""
    from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    stage.SetStartTimeCode(FRAME)  # the frame `gi inspect` (no frame given) opens the shutter around
    stage.SetEndTimeCode(FRAME)
    camera = UsdGeom.Camera.Define(stage, "/Camera")
    camera.CreateProjectionAttr(UsdGeom.Tokens.orthographic)
    camera.CreateHorizontalApertureAttr(10.0 * RESOLUTION[0] / PIXELS_PER_UNIT)  # tenths of a unit
    camera.CreateVerticalApertureAttr(10.0 * RESOLUTION[1] / PIXELS_PER_UNIT)
    camera.CreateClippingRangeAttr(Gf.Vec2f(0.1, 100))
    camera_translate = camera.AddTranslateOp()
    camera_translate.Set(Gf.Vec3d(0, 0, 10))
    camera.CreateShutterOpenAttr(shutter[0])
    camera.CreateShutterCloseAttr(shutter[1])
    if kind not in LIGHT_KINDS:
        UsdLux.DomeLight.Define(stage, "/Dome")
    material = UsdShade.Material.Define(stage, "/Grey")
    shader = UsdShade.Shader.Define(stage, "/Grey/Surface")
    shader.CreateIdAttr("UsdPreviewSurface")
    shader.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(albedo))
    material.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    # Time samples one frame either side of FRAME: USD interpolates linearly, so the object is at
    # x = -travel/2 when the shutter opens and at +travel/2 when it closes.
    span = SHUTTER[1] - SHUTTER[0]
    offset = {FRAME - 1: -travel / span, FRAME + 1: travel / span}

    def quad(path, dx=0.0):
        mesh = UsdGeom.Mesh.Define(stage, path)
        mesh.CreateFaceVertexCountsAttr([4])
        mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
        h = SIZE / 2
        mesh.CreatePointsAttr([Gf.Vec3f(-h + dx, -5, 0), Gf.Vec3f(h + dx, -5, 0), Gf.Vec3f(h + dx, 5, 0),
                               Gf.Vec3f(-h + dx, 5, 0)])
        return mesh

    if backdrop:
        UsdShade.MaterialBindingAPI.Apply(quad("/Backdrop").GetPrim()).Bind(material)
        UsdGeom.Mesh(stage.GetPrimAtPath("/Backdrop")).AddTranslateOp().Set(Gf.Vec3d(0, 0, -1))
    if kind == "sphere light":
        moving = UsdLux.SphereLight.Define(stage, "/Object")
        moving.CreateRadiusAttr(SIZE / 2)
    elif kind == "rect light":
        moving = UsdLux.RectLight.Define(stage, "/Object")
        moving.CreateWidthAttr(SIZE)
        moving.CreateHeightAttr(10.0)
    elif kind in ("sphere", "camera"):
        moving = UsdGeom.Sphere.Define(stage, "/Object")
        moving.CreateRadiusAttr(SIZE / 2)
        if kind == "camera":
            for frame, dx in offset.items():
                camera_translate.Set(Gf.Vec3d(-dx, 0, 10), frame)
    elif kind == "quad":
        moving = quad("/Object")
    elif kind == "deforming quad":
        moving = quad("/Object")
        for frame, dx in offset.items():
            h = SIZE / 2
            moving.GetPointsAttr().Set([Gf.Vec3f(-h + dx, -5, 0), Gf.Vec3f(h + dx, -5, 0),
                                        Gf.Vec3f(h + dx, 5, 0), Gf.Vec3f(-h + dx, 5, 0)], frame)
    elif kind == "point instancer":
        moving = UsdGeom.PointInstancer.Define(stage, "/Object")
        prototype = quad("/Object/Prototypes/Quad")
        UsdShade.MaterialBindingAPI.Apply(prototype.GetPrim()).Bind(material)
        moving.CreatePrototypesRel().SetTargets([prototype.GetPath()])
        moving.CreateProtoIndicesAttr([0])
        moving.CreatePositionsAttr().Set([Gf.Vec3f(0, 0, 0)], FRAME)
        # Velocities are per second: travel / span per frame, timeCodesPerSecond frames a second.
        moving.CreateVelocitiesAttr().Set(
            [Gf.Vec3f(travel / span * stage.GetTimeCodesPerSecond(), 0, 0)], FRAME)
    elif kind == "instance":
        source = stage.CreateClassPrim("/QuadSource")
        UsdShade.MaterialBindingAPI.Apply(quad("/QuadSource/Quad").GetPrim()).Bind(material)
        moving = UsdGeom.Xform.Define(stage, "/Object")
        moving.GetPrim().GetReferences().AddInternalReference(source.GetPath())
        moving.GetPrim().SetInstanceable(True)
    if kind not in ("deforming quad", "point instancer", "camera"):
        translate = moving.AddTranslateOp()
        for frame, dx in offset.items():
            translate.Set(Gf.Vec3d(dx, 0, 0), frame)
    if kind == "rect light":
        moving.AddRotateYOp().Set(180.0)  # a rect light emits along its -Z: towards the camera
    if kind not in ("instance", "point instancer", *LIGHT_KINDS):
        UsdShade.MaterialBindingAPI.Apply(moving.GetPrim()).Bind(material)
    stage.Save()
    return path


def render(path, spp=SPP, seed=0):
    from gi import _core
    from gi.render import render_settings
    from gi.loader import load_stage
    loaded = load_stage(path, time=FRAME)
    settings = render_settings(loaded, "path", {}, spp, seed, 0, 0.0, RESOLUTION, "box")
    result = _core.render(loaded.scene, settings)
    return np.asarray(result.color), loaded


def profile_variance(image, kind="sphere"):
    """The variance, in pixels^2, of the coverage profile along x (column means of 1 - image; of
    the image for a light, of radiance 1 against black)."""
    column_means = image[..., 1].mean(axis=0)
    coverage = column_means if kind in LIGHT_KINDS else 1 - column_means
    x = np.arange(len(coverage)) + 0.5
    mean = (coverage * x).sum() / coverage.sum()
    return float((coverage * (x - mean) ** 2).sum() / coverage.sum())


# The blurred profile is the object's profile convolved with a box of the travel (time is uniform
# over the shutter) and with a box of one pixel (each pixel averages its footprint): variances add.
# A disc of radius r projected on x has variance r^2 / 4; a box of width w, w^2 / 12.
PIXEL = 1.0
TRAVEL_PX = TRAVEL * PIXELS_PER_UNIT
SIZE_PX = SIZE * PIXELS_PER_UNIT


def analytic_variance(kind, travel_px=TRAVEL_PX):
    shape = (SIZE_PX / 2) ** 2 / 4 if kind in ("sphere", "camera", "sphere light") else SIZE_PX ** 2 / 12
    return shape + travel_px ** 2 / 12 + PIXEL ** 2 / 12


def width(variance):
    """The width of a box with this variance: the blurred object's width as one number."""
    return float(np.sqrt(12 * variance))


# Tolerance: the 5% on the width. Its noise part is far below it: over seeds 0-7 at 64 spp
# the measured width is within 0.19% of the analytic one for every kind (std 0.07% at most, so
# 4 sigma is 0.28%; the moving lights 0.05%, std 0.07%); unblurred, the model is good to 0.8% (the
# pixel term is approximate). Mistakes
# in the time (not sampled, half the shutter, one step) move the width by 37-60% (analytic).
WIDTH_TOLERANCE = 0.05


KINDS = ["sphere", "quad", "deforming quad", "instance", "point instancer", "camera", "sphere light", "rect light"]


@needs_core
@pytest.mark.parametrize("kind", KINDS)
def test_an_object_crossing_the_frame_blurs_to_the_analytic_width(tmp_path, kind):
    image, loaded = render(motion_stage(tmp_path / "moving.usda", kind))
    expected = width(analytic_variance(kind))
    measured = width(profile_variance(image, kind))
    assert abs(measured - expected) / expected < WIDTH_TOLERANCE, (kind, measured, expected)
    moving_path = "/Camera" if kind == "camera" else "/Object"
    assert list(loaded.moving) == [moving_path], loaded.moving
    assert loaded.moving[moving_path] == ["deformation" if kind == "deforming quad" else "transform"]
    stats = loaded.scene.stats()
    # What moves as what: (instances, shapes, lights).
    moving = {"camera": (0, 0, 0), "instance": (1, 0, 0), "point instancer": (1, 0, 0), "sphere light": (0, 0, 1),
              "rect light": (0, 0, 1)}.get(kind, (0, 1, 0))
    assert (stats["moving_instances"], stats["moving_shapes"], stats["moving_lights"]) == moving
    # Unblurred it would be the object's own width: the test tells the two apart.
    assert abs(width(analytic_variance(kind, 0)) - expected) / expected > 10 * WIDTH_TOLERANCE


@needs_core
def test_the_hit_point_and_normal_move_with_the_geometry(tmp_path):
    """A grey convex object under a uniform dome of radiance 1 reflects exactly its albedo (every
    bounce leaves it), so the image darkens by (1 - albedo) times the coverage a black one has with
    the same camera rays. A hit point or normal taken from where the object is not at the ray's time
    sends bounces into the object or off the wrong side, and the image darkens more."""
    albedo = 0.5

    def darkening_per_coverage(travel):
        black, _ = render(motion_stage(tmp_path / f"black{travel}.usda", "sphere", travel=travel))
        grey, _ = render(motion_stage(tmp_path / f"grey{travel}.usda", "sphere", travel=travel, albedo=albedo))
        return (1 - grey).sum() / ((1 - albedo) * (1 - black).sum())
    # Against the same sphere standing still, which has the same ratio up to noise (the ratio is not
    # exactly 1: UsdPreviewSurface's specular lobe takes a share of the albedo). Tolerance: over seeds
    # 0-7 at 64 spp the ratio's std is 0.26% moving and 0.12% still (measured), so the quotient's is
    # 0.29%, and 4 sigma is 1.2%.
    assert darkening_per_coverage(TRAVEL) / darkening_per_coverage(0.0) == pytest.approx(1, abs=0.012)


@needs_core
@pytest.mark.parametrize("kind", ["sphere", "sphere light", "rect light"])
def test_nothing_moving_renders_bit_identically_with_and_without_a_shutter(tmp_path, kind):
    # A grey sphere: paths bounce, so every sampler dimension a path draws is compared. A light
    # (its translation time-sampled, standing still) lights a grey backdrop: light samples too.
    shuttered = motion_stage(tmp_path / "shuttered.usda", kind, travel=0.0, albedo=0.5, backdrop=kind in LIGHT_KINDS)
    instant = motion_stage(tmp_path / "instant.usda", kind, shutter=(0.0, 0.0), travel=0.0, albedo=0.5,
                           backdrop=kind in LIGHT_KINDS)
    with_shutter, loaded = render(shuttered, spp=16)
    without, _ = render(instant, spp=16)
    assert loaded.shutter is not None and loaded.moving == {}
    stats = loaded.scene.stats()
    assert stats["moving_shapes"] == stats["moving_instances"] == stats["moving_lights"] == 0
    assert with_shutter.max() > 0
    assert np.array_equal(with_shutter, without)


@needs_core
def test_render_settings_can_disable_motion_blur(tmp_path):
    from pxr import Usd, UsdRender
    path = motion_stage(tmp_path / "moving.usda", "sphere")
    stage = Usd.Stage.Open(str(path))
    settings = UsdRender.Settings.Define(stage, "/Render/Settings")
    settings.CreateDisableMotionBlurAttr(True)
    stage.GetRootLayer().Save()
    image, loaded = render(path)
    assert loaded.shutter is None and loaded.moving == {}
    assert width(profile_variance(image)) == pytest.approx(width(analytic_variance("sphere", 0)), rel=WIDTH_TOLERANCE)


@needs_core
def test_a_shutter_closing_before_it_opens_warns_naming_the_camera_and_renders_without_blur(tmp_path):
    image, loaded = render(motion_stage(tmp_path / "backwards.usda", "sphere", shutter=(0.25, -0.25)))
    warnings = [w for w in loaded.scene.warnings() if "shutter" in w]
    assert len(warnings) == 1 and "/Camera" in warnings[0], loaded.scene.warnings()
    assert loaded.shutter is None and loaded.moving == {}
    # The sphere stands where it is at the frame (x = 0), unblurred.
    assert width(profile_variance(image)) == pytest.approx(width(analytic_variance("sphere", 0)), rel=WIDTH_TOLERANCE)


@needs_core
def test_inspect_reports_moving_prims_and_says_nothing_of_motion_when_nothing_moves(tmp_path):
    from conftest import run_gi
    moving = run_gi("inspect", motion_stage(tmp_path / "moving.usda", "deforming quad")).stdout
    assert "motion blur" in moving and "/Object" in moving and "deformation" in moving, moving
    still = run_gi("inspect", motion_stage(tmp_path / "still.usda", "sphere", travel=0.0)).stdout
    assert "motion" not in still.lower(), still


def test_step_times_keep_the_authored_samples_inside_the_shutter():
    from gi.motion import MAX_STEPS, Shutter, step_times
    shutter = Shutter(0.75, 1.25)
    assert step_times(shutter, []) == [0.75, 1.25]
    assert step_times(shutter, [0, 1, 2]) == [0.75, 1.0, 1.25]          # even: the samples themselves
    uneven = step_times(shutter, [0.8, 1.0])                              # as fine as the closest pair
    assert len(uneven) == 11 and min(abs(t - 0.8) for t in uneven) < 1e-12
    assert len(step_times(shutter, [0.75 + 1e-6])) == MAX_STEPS          # capped


def test_a_changing_radius_becomes_a_scale_in_each_step(tmp_path, fake_scene):
    from pxr import Usd, UsdGeom
    from gi.loader import load_stage
    path = motion_stage(tmp_path / "growing.usda", "sphere", travel=0.0)
    stage = Usd.Stage.Open(str(path))
    radius = UsdGeom.Sphere(stage.GetPrimAtPath("/Object")).GetRadiusAttr()
    radius.Set(0.5, FRAME - 1)
    radius.Set(1.5, FRAME + 1)  # 0.875 at shutter open (frame 0.75), 1.125 at close (1.25)
    stage.GetRootLayer().Save()
    loaded = load_stage(path, fake_scene, time=FRAME)
    steps = fake_scene.spheres[0].motion_transforms
    assert loaded.moving == {"/Object": ["transform"]}
    radius_at_frame = fake_scene.spheres[0].radius
    scales = [np.cbrt(abs(np.linalg.det(step[:3, :3]))) * radius_at_frame for step in steps]
    assert scales == pytest.approx([0.875, 1.125])
