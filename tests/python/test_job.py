"""Tiles and farm jobs: a data window equals the whole image there bit for bit; `gi job` writes an
Open Job Description bundle that `openjd check` accepts and `openjd run` renders into the frames a
single `gi render --frames` writes, bit for bit; failures name the task, the file or the flag."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import CORNELL, SOURCE, SOURCE_HAS_CORE, run_gi
from test_frames import animated_ball_stage

OPENJD = Path(sys.executable).parent / "openjd"  # openjd-cli, installed by scripts/install-deps.sh


def render_window(integrator, pixel_filter, window, size=(21, 18)):
    from gi import _core
    from gi.loader import load_stage
    settings = _core.RenderSettings()
    settings.width, settings.height = size
    settings.spp, settings.integrator, settings.seed, settings.filter = 3, integrator, 11, pixel_filter
    settings.data_window = window
    if integrator == "progressivePhotonMap":
        settings.params = {"photonsPerPass": 20000}  # enough photons to light the box; keeps the test short
    return _core.render(load_stage(CORNELL).scene, settings)


# The path tracer, a view-driven cache (records from the whole image's pixel centres) and the
# progressive photon map (a photon pass per sample index). Every integrator was checked the same
# way at 40x36 (see gi/tiles.py); three keep the test short.
@pytest.mark.parametrize("integrator", ["path", "irradianceCache", "progressivePhotonMap"])
@pytest.mark.parametrize("pixel_filter", ["box", "gaussian"])
def test_tiles_equal_the_whole_image_bit_for_bit(integrator, pixel_filter):
    from gi.tiles import Tiling, tile_window
    whole = render_window(integrator, pixel_filter, (0, 0, 0, 0))
    merged = {name: np.zeros_like(np.asarray(getattr(whole, name))) for name in ("color", "depth", "normal", "albedo",
                                                                                   "prim_id", "instance_id")}
    for index in range(4):
        x0, y0, x1, y1 = tile_window(Tiling(2, 2, index), 21, 18)
        tile = render_window(integrator, pixel_filter, (x0, y0, x1, y1))
        assert tile.data_window == (x0, y0, x1, y1)
        for name, image in merged.items():
            image[y0:y1, x0:x1] = np.asarray(getattr(tile, name))[y0:y1, x0:x1]
    for name, image in merged.items():
        assert np.array_equal(image, np.asarray(getattr(whole, name))), name
    assert np.asarray(whole.color).mean() > 0.01


def test_a_data_window_outside_the_image_is_refused():
    with pytest.raises(ValueError, match="is not inside the 21x18 image"):
        render_window("path", "box", (10, 0, 30, 5))


def gi_wrapper(tmp_path):
    """A `gi` command for the job's tasks: this checkout's gi, as run_gi runs it."""
    script = tmp_path / "gi"
    path = f"PYTHONPATH={SOURCE} " if SOURCE_HAS_CORE else ""
    script.write_text(f"#!/bin/sh\n{path}exec {sys.executable} -m gi \"$@\"\n")
    script.chmod(0o755)
    return script


def openjd(*args):
    return subprocess.run([str(OPENJD), *map(str, args)], capture_output=True, text=True)


def openjd_run(bundle, tmp_path, last_step, **overrides):
    """openjd run of the bundle's last step and what it depends on, with the bundle's parameter values."""
    values = {p["name"]: p["value"] for p in json.loads((bundle / "parameter_values.yaml").read_text())["parameterValues"]}
    values.update(Gi=str(gi_wrapper(tmp_path)), **overrides)
    return openjd("run", bundle / "template.yaml", "-p", json.dumps(values), "--step", last_step, "--run-dependencies")


RENDER_OPTIONS = ("--spp", 3, "--resolution", 20, 14, "--filter", "gaussian", "--seed", 2)


def test_job_with_tiles_run_by_openjd_equals_one_process_bit_for_bit(tmp_path):
    _, scene = animated_ball_stage(tmp_path)
    bundle = tmp_path / "bundle"
    proc = run_gi("job", scene, "--frames", "1-4", "--chunk", 4, "--tiles", "2x2", "-o", bundle, "--", *RENDER_OPTIONS)
    assert "deadline bundle submit" in proc.stdout and "5 tasks" in proc.stdout
    check = openjd("check", bundle / "template.yaml")
    assert check.returncode == 0, check.stdout + check.stderr
    run = openjd_run(bundle, tmp_path, "MergeTiles")
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr
    run_gi("render", scene, "--frames", "1-4", *RENDER_OPTIONS, "--no-png", "-o", tmp_path / "single" / "anim.####.exr")
    from gi import _core
    for frame in range(1, 5):
        single, single_meta = _core.read_image(str(tmp_path / "single" / f"anim.{frame:04d}.exr"))
        merged, merged_meta = _core.read_image(str(bundle / "frames" / f"anim.{frame:04d}.exr"))
        assert merged_meta["channels"] == single_meta["channels"]
        assert np.array_equal(merged, single), frame
        assert merged_meta["gi:seed"] == str(2 + frame) and merged_meta["gi:tiles"] == "4"


def test_job_without_tiles_renders_chunks(tmp_path):
    _, scene = animated_ball_stage(tmp_path)
    bundle = tmp_path / "bundle"
    run_gi("job", scene, "--frames", "2-4:2", "--chunk", 1, "-o", bundle, "--", "--spp", 1, "--resolution", 8, 8)
    template = json.loads((bundle / "template.yaml").read_text())
    assert [step["name"] for step in template["steps"]] == ["Render"]
    defaults = {p["name"]: p.get("default") for p in template["parameterDefinitions"]}
    assert defaults["Frames"] == "2,4" and defaults["ChunkSize"] == 1
    assert openjd("check", bundle / "template.yaml").returncode == 0
    run = openjd_run(bundle, tmp_path, "Render")
    assert run.returncode == 0, run.stdout[-3000:]
    assert sorted(p.name for p in (bundle / "frames").glob("*.exr")) == ["anim.0002.exr", "anim.0004.exr"]


def test_a_failing_task_is_reported_with_its_parameters_and_log(tmp_path):
    _, scene = animated_ball_stage(tmp_path)
    bundle = tmp_path / "bundle"
    run_gi("job", scene, "--frames", "1-2", "-o", bundle, "--", "--spp", 1, "--resolution", 8, 8)
    run = openjd_run(bundle, tmp_path, "Render", SceneFile=str(tmp_path / "moved_away.usda"))
    assert run.returncode != 0
    assert "Frame(CHUNK[INT]) = 1" in run.stdout                            # which task
    assert f"gi: error: {tmp_path / 'moved_away.usda'}: no such file" in run.stdout  # its log


def test_a_tile_of_a_render_that_tiles_cannot_join_is_a_usage_error(tmp_path):
    proc = run_gi("render", CORNELL, "--tile", "2x2:0", "--time-limit", "1", "-o", tmp_path / "t.exr", check=False)
    assert proc.returncode == 2 and "--tile with --time-limit" in proc.stderr
    assert not (tmp_path / "t.exr").exists()


def test_merge_names_a_missing_tile(tmp_path):
    _, scene = animated_ball_stage(tmp_path)
    for index in (0, 1, 3):
        run_gi("render", scene, "--frames", "1", "--spp", 1, "--resolution", 8, 6, "--tile", f"2x2:{index}",
               "-o", tmp_path / f"t.####.tile{index}.exr")
    proc = run_gi("merge-tiles", tmp_path / "t.####.tile{tile}.exr", "--tiles", "2x2", "--frames", "1",
                  "-o", tmp_path / "m.####.exr", check=False)
    assert proc.returncode == 2 and f"{tmp_path / 't.0001.tile2.exr'}: missing tile" in proc.stderr


@pytest.mark.parametrize("options, message", [
    (("--tiles", "2x2", "--", "--time-limit", "5"), "--tiles with --time-limit"),
    (("--", "--spp", "0"), "not valid for gi render"),
    (("--", "--integrator", "direct", "--path-depth", "3"), "--path-depth is not a parameter of 'direct'"),
    (("--", "-o", "x.exr"), "-o is set by the job itself"),
    (("--tiles", "2x", "--"), "is not a tile"),
    (("--chunk", "151"), "at most 150 frames"),
    (("--tiles", "2x2", "--", "--integrator", "auto"), "--tiles with --integrator auto"),
    (("--chunk", "1", "--", "--integrator", "auto"), "--integrator auto with 2 chunks: each task would choose"),
    (("--tiles", "2x2", "--", "--denoise"), "--tiles with --denoise"),
])
def test_job_refuses_what_would_fail_on_the_farm(tmp_path, options, message):
    proc = run_gi("job", CORNELL, "--frames", "1-2", "-o", tmp_path / "bundle", *options, check=False)
    assert proc.returncode == 2 and message in proc.stderr, proc.stderr
    assert not (tmp_path / "bundle" / "template.yaml").exists()
