"""The parity stages (tests/parity/*.usda) through both hosts: usdrecord --renderer Gi and
`gi render`, same integrator, samples, seed and complexity, give the same image (both tessellate
with renderer/mesh_description.h and shade by renderer/usd_shading.h; tests/python/test_parity.py
checks the `gi` side's statistics). usdrecord hides dome lights from the camera unless told
(--enableDomeLightVisibility); `gi render` shows them, as the stages' dome does."""
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO, hdgi_errors, openusd_python, read_rgb, run_openusd, settings_layer
from test_usdrecord import gi_render_scene

sys.path.insert(0, str(REPO / "tests" / "parity"))
import stage_files  # noqa: E402  (the stages with the textures they name)

STAGES = [("holes", "low"), ("left_handed", "low"), ("face_varying_normals", "low"),
          ("subdivision", "low"), ("subdivision", "high"), ("subdivision_creases_corners", "veryhigh"),
          ("texture_st0", "low"), ("texture_varname", "low"), ("texture_missing", "low"),
          ("display_color", "low"), ("display_color_inherited", "low"), ("geom_subsets", "low"),
          ("instanced_materials", "low"), ("camera_offsets", "low"), ("preview_surface_defaults", "low")]
SPP, SEED, WIDTH = 16, 0, 240
# usdrecord's image height: the width over the camera's aperture aspect, truncated (frameRecorder.cpp);
# camera_offsets' 24 x 16.25 aperture makes it 162, an aspect other than the aperture's.
HEIGHTS = {"camera_offsets": 162}


@pytest.mark.parametrize("stage, complexity", STAGES)
def test_usdrecord_and_gi_render_agree(tmp_path, stage, complexity, integrator="path"):
    scene = stage_files.prepare(stage, tmp_path / "stage")
    session = settings_layer(tmp_path / "session.usda", integrator=integrator, samples=SPP, seed=SEED)
    output = tmp_path / f"{stage}-{complexity}-hydra.exr"
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--enableDomeLightVisibility", "--colorCorrectionMode", "disabled", "--imageWidth", str(WIDTH),
                          "--camera", "/World/Camera", "--complexity", complexity, "--sessionLayer", str(session),
                          str(scene), str(output)])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    hydra = read_rgb(output)
    height = HEIGHTS.get(stage, WIDTH)
    assert hydra.shape[:2] == (height, WIDTH)
    cli = gi_render_scene(tmp_path, scene, integrator, SPP, SEED, WIDTH, height, "--complexity", complexity)
    identical = (np.abs(hydra - cli).max(axis=-1) == 0).mean()
    print(f"{stage} at {complexity}: {100 * identical:.2f}% of pixels identical, mean {hydra.mean():.5f} "
          f"(usdrecord) / {cli.mean():.5f} (gi render)")
    assert np.array_equal(hydra, cli)


@pytest.mark.parametrize("scene_index", [True, False], ids=["scene index, absolute path", "legacy, relative path"])
def test_udim_tiles_agree(tmp_path, scene_index):
    """texture_udim.usda's tiles (tiles.<UDIM>.exr) in both hosts. UsdImaging's legacy delegate
    anchors a relative UDIM pattern to its layer, as gi's loader does; its scene index (OpenUSD
    24.11) hands the pattern over as authored, so there the stage names it by an absolute path."""
    scene = stage_files.prepare("texture_udim", tmp_path / "stage", absolute_udim=scene_index)
    session = settings_layer(tmp_path / "session.usda", integrator="path", samples=SPP, seed=SEED)
    output = tmp_path / "udim-hydra.exr"
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--colorCorrectionMode", "disabled", "--imageWidth", str(WIDTH), "--camera", "/World/Camera",
                          "--sessionLayer", str(session), str(scene), str(output)], scene_index=scene_index)
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    assert "was not found" not in result.stdout + result.stderr, result.stderr
    cli = gi_render_scene(tmp_path, scene, "path", SPP, SEED, WIDTH, WIDTH)
    assert np.array_equal(read_rgb(output), cli)
    tiles = stage_files.UDIM_TILES["tiles.<UDIM>.exr"]
    # The quad spans pixels 20-220 (0.01 units each): its quarters' centres, (row, column) -> colour.
    centres = {(170, 70): tiles[1001], (170, 170): tiles[1002], (70, 70): tiles[1011],
               (70, 170): stage_files.UDIM_FALLBACK}
    for (row, column), colour in centres.items():
        assert np.allclose(cli[row, column], colour), ((row, column), cli[row, column], colour)


@pytest.mark.parametrize("stage", ["emissive_instances", "emissive_point_instances"])
def test_emissive_instances_emit_their_photons_alike(tmp_path, stage):
    """Twelve emissive lamp instances (native, or by a point instancer): the renderer orders
    emissive instances by name, so both hosts must name them in the same order."""
    test_usdrecord_and_gi_render_agree(tmp_path, stage, "low", "photonMapFinalGather")


@pytest.mark.parametrize("integrator", ["photonMapFinalGather", "progressivePhotonMap"])
def test_emissive_subsets_emit_their_photons_alike(tmp_path, integrator):
    """Photons leave the lights by index (the light BVH picks next-event lights by place, whatever
    their order): the two emissive subsets must be the same lights in the same order in both hosts,
    which name a subset's piece by the subset's path (hdGi's former 'mesh (material)' names sorted
    them the other way round: usdrecord's photon images then differed)."""
    test_usdrecord_and_gi_render_agree(tmp_path, "emissive_subsets", "low", integrator)


def test_editing_a_readers_varname_repicks_the_uvs(tmp_path):
    """In one session, texture_varname's reader switched from uvSet1 to the mirrored decoy st and
    back: the mesh re-reads its primvars (hdGi marks rprims dirty when a material's reader names
    change), so the texture mirrors and then the first image comes back bit for bit."""
    scene = stage_files.prepare("texture_varname", tmp_path / "stage")
    script = REPO / "tests/hydra/scripts/record_varname_edit.py"
    result = run_openusd([openusd_python(), str(script), str(scene), str(tmp_path),
                          "/World/Tiles/Reader", "uvSet1", "st", "uvSet1"])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    upright, mirrored, back = (read_rgb(tmp_path / f"{i}-{n}.exr") for i, n in enumerate(["uvSet1", "st", "uvSet1"]))
    # The quad's bottom-left clamped corner square (x, y in -1..-0.5, st in [0, 0.25]^2) shows one
    # texel: red upright, green mirrored. The view is 2.4 units over 240 pixels, y down: columns
    # 21..68 and rows 171..218 lie inside it.
    corner = (slice(171, 219), slice(21, 69))
    assert (upright[corner] == stage_files.RED).all() and (mirrored[corner] == stage_files.GREEN).all()
    assert np.array_equal(upright, back)


@pytest.mark.parametrize("policy, pixel_aspect, inherited",
                         [(*case, False) for case in stage_files.CONFORM_CASES] + [("cropAperture", 1.0, True)])
def test_conform_policy_agrees(tmp_path, policy, pixel_aspect, inherited):
    """camera_conform.usda through a RenderProduct (usdrecord renders the settings' resolution and
    framing only for products; without one it sizes the image to the camera's aspect and lets
    Hydra's window policy conform it): both hosts follow the settings' aspectRatioConformPolicy
    and pixelAspectRatio through renderer/camera_framing.h, the product's own over the settings'
    (a decoy there), or inherited from the settings, and write the same beauty and depth bit for
    bit.
    tests/python/test_parity.py checks where the rectangle lands for each case."""
    scene = stage_files.prepare("camera_conform", tmp_path / "stage")
    gi_settings = 'custom string gi:integrator = "path"\n' \
                  f'        custom int gi:samples = {SPP}\n        custom int gi:seed = {SEED}'
    hydra_layer = stage_files.conform_layer(tmp_path / "stage/hydra.usda", scene, policy, pixel_aspect,
                                            product=tmp_path / "hydra.exr", settings=gi_settings, inherited=inherited)
    cli_layer = stage_files.conform_layer(tmp_path / "stage/cli.usda", scene, policy, pixel_aspect,
                                          product=tmp_path / "cli.exr", settings=gi_settings, inherited=inherited)
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--colorCorrectionMode", "disabled", "--imageWidth", str(WIDTH), str(hydra_layer),
                          str(tmp_path / "usdrecord.exr")])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    assert not (tmp_path / "usdrecord.exr").exists(), "usdrecord did not render the product"
    subprocess.run([str(REPO / ".venv/bin/gi"), "render", str(cli_layer), "--integrator", "path", "--spp", str(SPP),
                    "--seed", str(SEED)], check=True, capture_output=True)
    from gi import _core
    (hydra, hydra_meta), (cli, cli_meta) = (_core.read_image(str(tmp_path / f"{host}.exr")) for host in ("hydra", "cli"))
    hydra, cli = np.asarray(hydra), np.asarray(cli)
    assert hydra_meta["channels"] == cli_meta["channels"] == ["R", "G", "B", "Depth"]
    assert hydra.shape == (120, 240, 4)
    identical = (hydra == cli).all(axis=-1).mean()
    print(f"{policy} {pixel_aspect}: {100 * identical:.2f}% of pixels identical, mean beauty "
          f"{hydra[..., :3].mean():.5f} (usdrecord) / {cli[..., :3].mean():.5f} (gi render)")
    assert np.array_equal(hydra, cli)


@pytest.mark.parametrize("stage", ["no_camera", "no_camera_z_up"])
def test_a_stage_without_a_camera_is_framed_alike(tmp_path, stage):
    """No camera anywhere: usdrecord frames the stage with its free camera (FrameRecorder's
    _ComputeCameraToFrameStage) and sizes the image to that camera's aspect (240 x 175); `gi render`
    frames it by the same rule (renderer/camera_framing.h's framingCamera, on the stage's bounding
    box and up axis), so at usdrecord's size the images are identical (before the shared rule the
    loader's own 36 mm camera matched on 44% and 47% of the pixels)."""
    scene = stage_files.prepare(stage, tmp_path / "stage")
    session = settings_layer(tmp_path / "session.usda", integrator="path", samples=SPP, seed=SEED)
    output = tmp_path / f"{stage}-hydra.exr"
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--enableDomeLightVisibility", "--colorCorrectionMode", "disabled", "--imageWidth", str(WIDTH),
                          "--sessionLayer", str(session), str(scene), str(output)])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    hydra = read_rgb(output)
    assert hydra.shape[:2] == (175, WIDTH)  # int(240 / (20.955 / 15.2908)), GfCamera's default aperture
    cli = gi_render_scene(tmp_path, scene, "path", SPP, SEED, WIDTH, 175)
    assert (hydra != 1).any(axis=-1).mean() > 0.4  # the quad fills much of the frame
    assert np.array_equal(hydra, cli)
