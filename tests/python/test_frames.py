"""gi render --frames: time codes in one process, per-frame seeds and names; the earliest time
without --frames; the scene reused only when nothing but the camera moves."""
import numpy as np
import pytest

from conftest import new_stage, run_gi


def animated_ball_stage(tmp_path, animate_camera=False, animate_ball=True, name="anim.usda"):
    """A floor, a sphere light and a ball at x = -1.5 + 0.6 f on frames 1..4 (time samples only);
    or a still ball and a camera moving along x."""
    from pxr import Gf, UsdGeom, UsdLux
    stage, path = new_stage(tmp_path, name)
    camera_op = UsdGeom.Camera.Get(stage, "/Camera").GetOrderedXformOps()[0]
    floor = UsdGeom.Cube.Define(stage, "/Floor")
    floor.AddTranslateOp().Set(Gf.Vec3d(0, -1.5, 0))
    floor.AddScaleOp().Set(Gf.Vec3f(3, 0.1, 3))
    ball = UsdGeom.Sphere.Define(stage, "/Ball").AddTranslateOp()
    for frame in range(1, 5):
        if animate_ball:
            ball.Set(Gf.Vec3d(-1.5 + 0.6 * frame, 0, 0), frame)
        if animate_camera:
            camera_op.Set(Gf.Vec3d(0.3 * frame, 0, 5), frame)
    light = UsdLux.SphereLight.Define(stage, "/Light")
    light.AddTranslateOp().Set(Gf.Vec3d(0, 3, 3))
    light.CreateIntensityAttr(30)
    light.CreateRadiusAttr(0.5)
    stage.Save()
    return stage, path


def read(path):
    from gi import _core
    return _core.read_image(str(path))


# -- range expressions and names -----------------------------------------------------------------

def test_frame_ranges_parse_and_print_as_openjd_range_expressions():
    from gi.frames import chunks, format_frames, parse_frames
    assert parse_frames("1-5") == [1, 2, 3, 4, 5]
    assert parse_frames("1-10:3") == [1, 4, 7, 10]
    assert parse_frames("7") == [7]
    assert parse_frames("1-3,10,2") == [1, 2, 3, 10]  # each frame once, first order kept
    assert parse_frames("-2-1") == [-2, -1, 0, 1]
    for bad in ("5-1", "1-4:0", "a", "1-", ""):
        with pytest.raises(ValueError):
            parse_frames(bad)
    assert format_frames([1, 2, 3, 4]) == "1-4"
    assert format_frames([1, 3, 5, 9]) == "1-5:2,9"
    assert chunks(list(range(1, 11)), 4) == ["1-4", "5-8", "9-10"]
    for frames in ([1, 2, 3, 10, 12, 14], [5], [-3, -1, 1]):
        assert parse_frames(format_frames(frames)) == frames


def test_frame_tokens_in_paths():
    from gi.frames import frame_path, has_frame_token
    assert frame_path("out/shot.####.exr", 7) == "out/shot.0007.exr"
    assert frame_path("out/shot.$F4.exr", 12) == "out/shot.0012.exr"
    assert frame_path("out/shot.$F.exr", 12) == "out/shot.12.exr"
    assert frame_path("out/shot.##.exr", 123) == "out/shot.123.exr"
    assert not has_frame_token("out/shot.exr")


# -- which time ----------------------------------------------------------------------------------

def test_without_frames_the_stage_is_read_at_the_earliest_time(tmp_path, fake_scene):
    """A translate authored only as time samples has no value at USD's default time (the ball
    would sit at the origin); usdrecord renders the earliest time, where it has its first sample."""
    from gi.loader import load_stage
    _, path = animated_ball_stage(tmp_path)
    load_stage(path, fake_scene)
    ball = next(s for s in fake_scene.spheres if s.name == "/Ball")
    assert np.allclose(ball.transform[3, :3], (-0.9, 0, 0))


# -- rendering frames ----------------------------------------------------------------------------

def test_frames_render_each_time_code_with_its_own_seed_and_name(tmp_path):
    _, path = animated_ball_stage(tmp_path)
    common = ("--spp", 2, "--resolution", 24, 16, "--no-png", "--seed", 5)
    proc = run_gi("render", path, "--frames", "1-3", *common, "-o", tmp_path / "seq" / "shot.$F4.exr")
    assert [line.split(":")[0].rsplit(" ", 1)[-1] for line in proc.stdout.splitlines()] == ["1", "2", "3"]
    images = {}
    for frame in (1, 2, 3):
        pixels, meta = read(tmp_path / "seq" / f"shot.{frame:04d}.exr")
        assert meta["gi:frame"] == str(frame) and meta["gi:seed"] == str(5 + frame)
        images[frame] = pixels
    # The ball moves: its depth (noise-free) differs between frames.
    z = [images[f][..., 3] for f in (1, 2, 3)]
    assert not np.array_equal(z[0], z[1]) and not np.array_equal(z[1], z[2])
    # A frame rendered alone (a farm chunk of one) equals the same frame of the sequence.
    run_gi("render", path, "--frames", "2", *common, "-o", tmp_path / "alone.exr")
    alone, _ = read(tmp_path / "alone.exr")
    assert np.array_equal(alone, images[2])
    # Without --frames the stage is read at its earliest sample (the ball as on frame 1) and seeded
    # by its start time code, as usdrecord renders and hdGi seeds it: 0 when none is authored, else
    # that frame's seed, the image then frame 1's bit for bit.
    run_gi("render", path, *common, "-o", tmp_path / "no_frames.exr")
    first, meta = read(tmp_path / "no_frames.exr")
    assert meta["gi:seed"] == "5" and not np.array_equal(first, images[1])
    from pxr import Usd
    stage = Usd.Stage.Open(str(path))
    stage.SetStartTimeCode(1)
    stage.Save()
    run_gi("render", path, *common, "-o", tmp_path / "start_1.exr")
    first, meta = read(tmp_path / "start_1.exr")
    assert meta["gi:seed"] == "6" and np.array_equal(first, images[1])


def test_frame_seeds_are_seed_plus_the_whole_frame():
    """One rule for both hosts (renderer/render_vars.h): hdGi seeds the host's current frame so."""
    from gi.frames import frame_seed
    assert [frame_seed(5, f) for f in (1, 2, 1001)] == [6, 7, 1006]
    assert frame_seed(0, -3) == 2**32 - 3 and frame_seed(2**32 - 1, 2) == 1  # modulo 2^32
    assert frame_seed(5, 2.4) == 7 and frame_seed(5, 2.6) == 8  # rounded, as file names are
    assert frame_seed(5, float("nan")) == 5  # USD's default time: no frame


def test_frames_of_a_still_stage_have_decorrelated_noise(tmp_path):
    """Nothing moves, so only the per-frame seed can tell frames apart (seed + frame)."""
    from pxr import Gf, UsdGeom, UsdLux
    stage, path = new_stage(tmp_path)
    UsdGeom.Sphere.Define(stage, "/Ball")
    UsdLux.SphereLight.Define(stage, "/Light").AddTranslateOp().Set(Gf.Vec3d(0, 3, 3))
    stage.Save()
    proc = run_gi("render", path, "--frames", "1-2", "--spp", 1, "--resolution", 16, 16, "--no-png",
                  "-o", tmp_path / "still.####.exr")
    assert "has no time samples" in proc.stderr and "--frames 1-2" in proc.stderr
    first, _ = read(tmp_path / "still.0001.exr")
    second, _ = read(tmp_path / "still.0002.exr")
    assert not np.array_equal(first[..., :3], second[..., :3])  # other samples, so other noise


def render_sequence(path, frames, rebuild=False):
    """{frame: colour} through gi.sequence, optionally forcing a scene per frame."""
    from gi.render import render_loaded, render_settings
    from gi.sequence import Sequence
    sequence = Sequence(path, frames)
    out = {}
    for frame in sequence:
        if rebuild and not frame.rebuilt:
            from gi.loader import load_stage
            frame.loaded, frame.camera = load_stage(path, time=frame.number), None
        settings = render_settings(frame.loaded, "path", {}, 2, frame.number, 0, 0.0, (24, 16), "box")
        out[frame.number] = np.asarray(render_loaded(frame.loaded, settings, "", camera=frame.camera).color)
    return sequence, out


def test_camera_move_reuses_the_scene_and_equals_a_scene_per_frame(tmp_path):
    _, path = animated_ball_stage(tmp_path, animate_camera=True, animate_ball=False)
    sequence, reused = render_sequence(path, [1, 3])
    assert sequence.reuse == "camera"
    _, rebuilt = render_sequence(path, [1, 3], rebuild=True)
    assert np.array_equal(reused[3], rebuilt[3])
    assert not np.array_equal(reused[1], reused[3])


def test_anything_but_the_camera_moving_rebuilds_the_scene(tmp_path):
    from pxr import Gf, UsdGeom, UsdLux, Usd
    from gi.frames import only_camera_moves
    _, path = animated_ball_stage(tmp_path, animate_camera=True, animate_ball=False)
    assert only_camera_moves(Usd.Stage.Open(str(path)), "/Camera")
    _, path = animated_ball_stage(tmp_path, animate_camera=True, animate_ball=True, name="both.usda")
    assert not only_camera_moves(Usd.Stage.Open(str(path)), "/Camera")
    # A light's intensity, and a moving rig that carries the camera and a gprim.
    stage, path = new_stage(tmp_path, "light.usda")
    intensity = UsdLux.SphereLight.Define(stage, "/Light").CreateIntensityAttr()
    intensity.Set(5.0, 1)
    intensity.Set(9.0, 2)
    assert not only_camera_moves(stage, "/Camera")
    rig = UsdGeom.Xform.Define(stage, "/Rig")
    rig.AddTranslateOp().Set(Gf.Vec3d(1, 0, 0), 1)
    rig.GetOrderedXformOps()[0].Set(Gf.Vec3d(2, 0, 0), 2)
    UsdGeom.Camera.Define(stage, "/Rig/Camera")
    stage.RemovePrim("/Light")
    assert only_camera_moves(stage, "/Rig/Camera")
    UsdGeom.Sphere.Define(stage, "/Rig/Ball")
    assert not only_camera_moves(stage, "/Rig/Camera")


# -- bad input -----------------------------------------------------------------------------------

def test_frames_outside_the_time_samples_warn_and_render(tmp_path):
    _, path = animated_ball_stage(tmp_path)
    proc = run_gi("render", path, "--frames", "3-6", "--spp", 1, "--resolution", 8, 8, "--no-png",
                  "-o", tmp_path / "o.####.exr")
    assert "--frames 3-6: frames 5-6 are outside" in proc.stderr and "(1 to 4)" in proc.stderr
    assert all((tmp_path / f"o.{f:04d}.exr").exists() for f in range(3, 7))


def test_one_output_name_for_many_frames_is_a_usage_error(tmp_path):
    _, path = animated_ball_stage(tmp_path)
    proc = run_gi("render", path, "--frames", "1-2", "-o", tmp_path / "one.exr", check=False)
    assert proc.returncode == 2 and "-o" in proc.stderr and "####" in proc.stderr
    proc = run_gi("render", path, "--frames", "4-1", check=False)
    assert proc.returncode == 2 and "ends before it starts" in proc.stderr


def ball_wall_and_pebbles_stage(tmp_path):
    """animated_ball_stage with a wall and a point instancer of three pebbles, all still."""
    from pxr import Gf, UsdGeom
    stage, path = animated_ball_stage(tmp_path)
    wall = UsdGeom.Cube.Define(stage, "/Wall")
    wall.AddTranslateOp().Set(Gf.Vec3d(0, 0, -3))
    wall.AddScaleOp().Set(Gf.Vec3f(3, 3, 0.1))
    pebbles = UsdGeom.PointInstancer.Define(stage, "/Pebbles")
    pebble = UsdGeom.Sphere.Define(stage, "/Pebbles/Prototypes/Pebble")
    pebble.CreateRadiusAttr(0.2)
    pebbles.CreatePrototypesRel().SetTargets([pebble.GetPath()])
    pebbles.CreateProtoIndicesAttr([0, 0, 0])
    pebbles.CreatePositionsAttr([(-1, -1.2, 1), (0, -1.2, 1), (1, -1.2, 1)])
    stage.Save()
    return path


def test_moving_prims_rebuild_only_their_own_bvh_and_frames_equal_scenes_built_alone(tmp_path, monkeypatch):
    """Frames after the second keep the BVH of everything that did not move (Scene.reuse_bvh_of):
    they build nothing (the ball, the one thing that moves, is a sphere tested beside the BVH);
    the images are those of each frame loaded alone."""
    from gi import sequence
    from gi.loader import load_stage
    from gi.render import render_loaded, render_settings
    # Whether keeping BVHs pays depends on frame times (test_long_frames_...); here it always does.
    monkeypatch.setattr(sequence, "STATIC_BVH_TRACE_COST", 0.0)
    path = ball_wall_and_pebbles_stage(tmp_path)
    built, kept = [], []
    for frame in sequence.Sequence(path, [1, 2, 3, 4]):
        assert frame.rebuilt
        settings = render_settings(frame.loaded, "path", {}, 2, frame.number, 0, 0.0, (24, 16), "box")
        image = np.asarray(render_loaded(frame.loaded, settings, "").color)
        built.append(int(frame.loaded.scene.stats()["primitives_built"]))
        kept.append(int(frame.loaded.scene.stats()["primitives_reused"]))
        alone = load_stage(path, time=frame.number)
        assert np.array_equal(image, np.asarray(render_loaded(alone, settings, "").color)), frame.number
    # Floor and wall 12 triangles each, the pebble prototype 1 sphere; the ball, a static sphere of
    # the top level in each frame, is tested beside the BVH (Scene::kDirectSpheres), never built.
    # Frame 2 gathers what did not move into one BVH (the prototype's is kept); then nothing is built.
    assert built == [25, 24, 0, 0], built
    assert kept == [0, 1, 25, 25], kept


def test_long_frames_build_one_flat_bvh(tmp_path, monkeypatch):
    """Tracing through the kept static BVH costs a little (one instance level): frames whose render
    takes longer than the whole scene's build over STATIC_BVH_TRACE_COST build a flat one."""
    from gi import sequence
    path = ball_wall_and_pebbles_stage(tmp_path)
    monkeypatch.setattr(sequence, "STATIC_BVH_TRACE_COST", 1e9)  # every frame "long"
    kept = []
    for frame in sequence.Sequence(path, [1, 2, 3]):
        frame.loaded.scene.commit()
        kept.append(int(frame.loaded.scene.stats()["primitives_reused"]))
    assert kept == [0, 0, 0], kept


def test_each_frame_says_what_its_bvh_built(tmp_path):
    import re
    path = ball_wall_and_pebbles_stage(tmp_path)
    proc = run_gi("render", path, "--frames", "1-3", "--spp", 1, "--resolution", 8, 8, "--no-png",
                  "-o", tmp_path / "o.####.exr")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert "(BVH: 25 primitives built, 0 kept from the previous frame)" in lines[0], lines
    # Whether later frames keep BVHs depends on measured frame times (the tests above).
    for line in lines[1:]:
        assert re.search(r"\(BVH: \d+ primitives built, \d+ kept from the previous frame\)$", line), lines
