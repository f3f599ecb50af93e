"""Incremental edits in one Hydra session: moving the sphere, removing and re-adding a prim,
changing a material and hiding a light show up in the next frame, and undoing an edit gives
back the very same image (renders are deterministic, so stale state would show)."""
import json

import numpy as np

from conftest import CORNELL, REPO, hdgi_errors, openusd_python, read_rgb, run_openusd


def test_edits_in_one_session(tmp_path):
    script = REPO / "tests/hydra/scripts/record_edits.py"
    result = run_openusd([openusd_python(), str(script), str(CORNELL), str(tmp_path), "96", "direct", "8"])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    images = {step["name"]: read_rgb(tmp_path / f"{step['name']}.exr")
              for step in json.loads((tmp_path / "steps.json").read_text())}
    for name, image in images.items():
        assert np.isfinite(image).all(), name

    def changed(a, b):
        return np.abs(images[a] - images[b]).max(axis=-1) > 1e-6

    moved = changed("original", "moved")
    # The sphere moved: its old and new footprints (and the shadow it casts) changed; the rest
    # of the direct-lit image did not.
    assert 0.005 < moved.mean() < 0.5, moved.mean()
    # Undo gives the same image: nothing stale stayed in the scene.
    assert not changed("original", "moved_back").any()
    assert changed("original", "removed").mean() > 0.1
    assert not changed("original", "readded").any()
    recolored = images["recolored"]
    assert recolored[..., 0].mean() < images["readded"][..., 0].mean() * 0.8
    # Only the rect light lights the box: hiding it leaves black.
    assert images["light_hidden"].max() < 1e-6


def test_auto_keeps_its_choice_through_edits(tmp_path):
    """gi:integrator auto chooses once in a session: its pilots are timed and may choose apart, and
    a session must not switch techniques (nor pay for pilots) at every edit or camera move. So the
    technique is chosen once, and undoing an edit gives back the very same image."""
    script = REPO / "tests/hydra/scripts/record_edits.py"
    result = run_openusd([openusd_python(), str(script), str(CORNELL), str(tmp_path), "64", "auto", "2", "1"])
    log = result.stdout + result.stderr
    assert not hdgi_errors(log), result.stderr
    assert log.count("hdGi: auto: chose ") == 1, log[-3000:]
    original, moved, moved_back = (read_rgb(tmp_path / f"{name}.exr") for name in ("original", "moved", "moved_back"))
    assert np.isfinite(original).all() and np.isfinite(moved).all()
    assert not np.array_equal(original, moved)
    assert np.array_equal(original, moved_back)
    # Choosing another technique and then auto again chooses anew.
    stats = REPO / "tests/hydra/scripts/record_stats.py"
    result = run_openusd([openusd_python(), str(stats), str(CORNELL), "64", "auto:autoHorizon=1", "2", "0", "reselect"])
    log = result.stdout + result.stderr
    assert not hdgi_errors(log), result.stderr
    assert log.count("hdGi: auto: chose ") == 2, log[-3000:]


def test_an_edit_reads_no_texture_again(tmp_path):
    """A scene edit rebuilds the renderer's scene; textures whose files did not change come from
    the session's image cache instead of being read again (Sponza's would take seconds)."""
    import json

    import matplotlib.image

    matplotlib.image.imsave(tmp_path / "wall.png", np.linspace(0, 1, 48).reshape(4, 4, 3))
    layer = tmp_path / "textured_cornell.usda"
    layer.write_text(f"""#usda 1.0
(
    subLayers = [@{CORNELL}@]
)
over "World"
{{
    over "Looks"
    {{
        over "White"
        {{
            over "Surface"
            {{
                color3f inputs:diffuseColor.connect = </World/Looks/White/Texture.outputs:rgb>
            }}
            def Shader "Texture"
            {{
                uniform token info:id = "UsdUVTexture"
                asset inputs:file = @./wall.png@
                float3 outputs:rgb
            }}
        }}
    }}
}}
""")
    script = REPO / "tests/hydra/scripts/record_stats.py"
    result = run_openusd([openusd_python(), str(script), str(layer), "32", "direct", "2", "0", "light"])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    report = json.loads(result.stdout.strip().splitlines()[-1])
    before, after = report["stats"], report["stats_after_edit"]
    assert before["textures"] == 1 and before["texturesRead"] == 1, before
    assert after["textures"] == 1 and after["texturesRead"] == 0, after
    assert after["sceneBuildSeconds"] > 0, after  # the edit did rebuild the scene
    assert before["nonFiniteSamples"] == 0 and after["nonFiniteSamples"] == 0, (before, after)


def test_moving_a_mesh_rebuilds_only_its_bvh(tmp_path):
    """An edit builds the BVH of what it changed only (gi::Scene::reuseBvhOf): each move of a
    mesh, the first included, builds the mesh alone; the rest stays in the BVH built at load, where
    the mesh's old self is masked."""
    script = REPO / "tests/hydra/scripts/record_stats.py"
    result = run_openusd([openusd_python(), str(script), str(CORNELL), "32", "direct", "2", "0", "move"])
    assert not hdgi_errors(result.stdout + result.stderr), result.stderr
    report = json.loads(result.stdout.strip().splitlines()[-1])
    initial, moves = report["stats"], report["stats_after_moves"]
    total = initial["primitivesBuilt"]
    assert initial["primitivesReused"] == 0 and total > 0, initial
    for move in moves:
        # The Cornell box's floor: 2 of its 10 BVH primitives (its sphere is tested beside the BVH).
        assert 0 < move["primitivesBuilt"] <= 0.2 * total, (report["moved"], move)
        assert move["primitivesBuilt"] + move["primitivesReused"] == total, move
        assert move["primitivesMasked"] == move["primitivesBuilt"], move
        assert move["nonFiniteSamples"] == 0, move


def test_hiding_or_rebinding_a_mesh_builds_no_bvh(tmp_path):
    """Hiding a mesh masks it in the BVH built at load, showing it again unmasks it, and binding
    another material changes no BVH: none of these edits builds one."""
    script = REPO / "tests/hydra/scripts/record_stats.py"
    for edit in ("hide", "material"):
        result = run_openusd([openusd_python(), str(script), str(CORNELL), "32", "direct", "2", "0", edit])
        assert not hdgi_errors(result.stdout + result.stderr), result.stderr
        report = json.loads(result.stdout.strip().splitlines()[-1])
        total = report["stats"]["primitivesBuilt"]
        first, second = report["stats_after_edits"]
        for after in (first, second):
            assert after["primitivesBuilt"] == 0 and after["nonFiniteSamples"] == 0, (edit, after)
            assert after["sceneBuildSeconds"] > 0, (edit, after)  # the edit did rebuild the scene
        masked = first["primitivesMasked"]
        assert (0 < masked < total) if edit == "hide" else masked == 0, (edit, first)
        assert first["primitivesReused"] == total - masked, (edit, first)
        assert second["primitivesMasked"] == 0 and second["primitivesReused"] == total, (edit, second)
