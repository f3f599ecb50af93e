"""The mesh parity stages (tests/parity/*.usda) through both hosts: usdrecord --renderer Gi and
`gi render`, same integrator, samples, seed and complexity, give the same image (both tessellate
with renderer/mesh_description.h; tests/python/test_parity.py checks the `gi` side's statistics)."""
import numpy as np
import pytest

from conftest import REPO, hdgi_errors, read_rgb, run_openusd, settings_layer
from test_usdrecord import gi_render_scene

PARITY = REPO / "tests" / "parity"
STAGES = [("holes", "low"), ("left_handed", "low"), ("face_varying_normals", "low"),
          ("subdivision", "low"), ("subdivision", "high"), ("subdivision_creases_corners", "veryhigh")]
SPP, SEED, WIDTH = 16, 0, 240


@pytest.mark.parametrize("stage, complexity", STAGES)
def test_usdrecord_and_gi_render_agree(tmp_path, stage, complexity):
    scene = PARITY / f"{stage}.usda"
    session = settings_layer(tmp_path / "session.usda", integrator="path", samples=SPP, seed=SEED)
    output = tmp_path / f"{stage}-{complexity}-hydra.exr"
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--colorCorrectionMode", "disabled", "--imageWidth", str(WIDTH), "--camera", "/World/Camera",
                          "--complexity", complexity, "--sessionLayer", str(session), str(scene), str(output)])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    hydra = read_rgb(output)
    cli = gi_render_scene(tmp_path, scene, "path", SPP, SEED, WIDTH, WIDTH, "--complexity", complexity)
    identical = (np.abs(hydra - cli).max(axis=-1) == 0).mean()
    print(f"{stage} at {complexity}: {100 * identical:.2f}% of pixels identical, covered {hydra.mean():.5f} "
          f"(usdrecord) / {cli.mean():.5f} (gi render)")
    assert np.array_equal(hydra, cli)
