"""usdview as a host: testusdview drives a real usdview window (Xvfb + Mesa llvmpipe) with Gi
selected and the scene camera, through tests/hydra/scripts/usdview_session.py."""
import json
import shutil
import subprocess

import numpy as np
import pytest

from conftest import CORNELL, OPENUSD, REPO, hdgi_errors, openusd_env

pytestmark = pytest.mark.skipif(not (OPENUSD / "bin/testusdview").exists() or not shutil.which("xvfb-run"),
                                reason="no testusdview in the OpenUSD build or no xvfb-run")


def read_png(path):
    from gi import _core
    pixels, _ = _core.read_image(str(path))
    return np.asarray(pixels, dtype=np.float64)[..., :3]


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    out = tmp_path_factory.mktemp("usdview")
    env = openusd_env()
    env["GI_USDVIEW_OUT"] = str(out)
    script = REPO / "tests/hydra/scripts/usdview_session.py"
    result = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", str(OPENUSD / "bin/testusdview"),
                             "--testScript", str(script), "--renderer", "Gi", "--camera", "/World/Camera",
                             str(CORNELL)], env=env, capture_output=True, text=True, timeout=1500)
    log = result.stdout + result.stderr
    (out / "usdview.log").write_text(log)
    assert result.returncode == 0, log[-4000:]
    results = json.loads((out / "results.json").read_text())
    return out, results, log


def test_no_errors_from_hdgi(session):
    _, _, log = session
    assert not hdgi_errors(log), "\n".join(hdgi_errors(log))


def test_gi_is_the_renderer_and_lists_every_integrator_parameter(session):
    from gi import _core
    _, results, _ = session
    assert results["renderer"] == "Gi"
    keys = set(results["settings"])
    assert {"gi:integrator", "convergedSamplesPerPixel", "gi:seed"} <= keys
    for info in _core.integrators():
        for param in info["params"]:
            assert f"gi:{info['name']}:{param['name']}" in keys


def test_settings_changes_restart_and_change_the_image(session):
    out, results, _ = session
    path, direct, noisy = (read_png(out / name) for name in ("cornell.png", "direct.png", "path_2spp.png"))
    again = read_png(out / "cornell_again.png")
    # Direct lighting has no indirect light: darker than the path tracer.
    assert direct.mean() < 0.9 * path.mean()
    # 2 samples are noisier than 16 (against the same 16-sample image rendered again).
    assert np.abs(noisy - again).mean() > np.abs(path - again).mean()
    assert results["spp2_stats"]["samples"] == 2
    for name in ("first_stats", "direct_stats", "spp2_stats"):
        assert results[name]["nonFiniteSamples"] == 0, (name, results[name])


def test_time_limit_is_kept(session):
    # Issue 16's bound for every host: within 5% + 0.2 s of the budget (tests/python/test_budgets.py
    # holds `gi render` to the same).
    _, results, _ = session
    for integrator, (limit, seconds, samples) in results["time_limit"].items():
        # `samples` counts whole passes: a budget that ends inside the first keeps its finished
        # pixels (unbiased, render.h) and warns if some pixel has none (here it may, on a busy
        # machine: the photon cache needs ~2.7 s for one sample at this size).
        print(f"gi:timeLimit {limit} s with {integrator}: {seconds:.2f} s, {samples} whole samples per pixel")
        assert abs(seconds - limit) <= 0.05 * limit + 0.2, (integrator, limit, seconds)


def test_picking_the_sphere_selects_it(session):
    _, results, _ = session
    assert results["picked"] == ["/World/GlassSphere"]


def test_pause_and_stop_within_100_ms(session):
    _, results, _ = session
    print(f"render thread's last tile after pause: {results['pause_latency'] * 1000:.0f} ms "
          f"(last tile before it {results['pause_idle'] * 1000:.0f} ms earlier), after stop: "
          f"{results['stop_latency'] * 1000:.0f} ms (before it {results['stop_idle'] * 1000:.0f} ms)")
    # The thread was rendering when asked (a tile ended within 0.5 s before the request, or just
    # after it, before the script read the stats: slightly negative; an idle thread, converged
    # 1.5 s earlier, would make any latency pass), and its last tile ended within 100 ms after.
    for what in ("pause", "stop"):
        assert results[f"{what}_idle"] < 0.5, results
        assert results[f"{what}_latency"] < 0.1, results


def test_edits_show_without_reload(session):
    out, _, _ = session
    base = read_png(out / "cornell.png")
    moved, recolored, dark = (read_png(out / n) for n in ("edit_moved.png", "edit_recolored.png",
                                                            "edit_light_hidden.png"))
    assert np.abs(moved - base).max() > 0.1
    assert recolored[..., 0].mean() < 0.8 * moved[..., 0].mean()
    # Only usdview's own axis overlay (thin GL lines) is left once the light is hidden.
    assert np.percentile(dark, 99) < 0.05


def test_memory_does_not_grow_over_camera_restarts(session):
    _, results, _ = session
    memory = results["resident_mb"]
    print("resident MB after each restart:", " ".join(f"{m:.0f}" for m in memory))
    assert memory[-1] <= 1.05 * memory[1]


def block_means(image, block=8):
    h, w = (image.shape[0] // block) * block, (image.shape[1] // block) * block
    return image[:h, :w].reshape(h // block, block, w // block, block, 3).mean(axis=(1, 3))


def gi_png(tmp_path, scene, size, name):
    output = tmp_path / f"{name}.exr"
    subprocess.run([str(REPO / ".venv/bin/gi"), "render", str(scene), "--integrator", "path", "--spp", "16",
                    "--seed", "0", "--resolution", str(size[0]), str(size[1]), "-o", str(output)],
                   check=True, capture_output=True)
    return read_png(output.with_suffix(".png"))


def test_camera_light_adds_light(session):
    out, _, _ = session
    assert read_png(out / "camera_light.png").mean() > 1.05 * read_png(out / "cornell.png").mean()


def test_converged_viewport_matches_gi_render(session, tmp_path):
    # Both through an sRGB display transform to 8 bits (usdview's default color correction, the
    # shipped OCIO config's sRGB view); compared in 8x8 blocks, which averages the sample noise
    # that differs where camera rays differ in the last bits.
    out, results, _ = session
    viewport = read_png(out / "cornell.png")
    assert list(viewport.shape[1::-1]) == results["viewport"]
    reference = gi_png(tmp_path, CORNELL, results["viewport"], "fresh")
    difference = np.abs(block_means(viewport) - block_means(reference)).mean()
    print(f"mean block difference {difference:.4f} (8-bit sRGB / 255)")
    assert difference < 0.02
    # README shows a copy of this screenshot (docs/usdview-cornell.png): refreshed only when it
    # has just been checked against `gi render`.
    target = REPO / "out/usdview-cornell.png"
    target.parent.mkdir(exist_ok=True)
    shutil.copyfile(out / "cornell.png", target)


def test_edited_viewport_matches_fresh_render_of_the_edited_scene(session, tmp_path):
    out, results, _ = session
    viewport = read_png(out / "edited.png")
    reference = gi_png(tmp_path, out / "edited.usda", results["viewport"], "edited")
    difference = np.abs(block_means(viewport) - block_means(reference)).mean()
    print(f"mean block difference after edits {difference:.4f}")
    assert difference < 0.02
