"""`gi render` takes the render settings prim's gi: settings as its defaults, as hdGi reads them
through Hydra (so usdrecord and `gi render` render a stage alike); flags given win; an unknown gi:
attribute warns naming the prim."""
import pytest

from gi.descriptors import HAVE_CORE

from conftest import CORNELL, run_gi

pytestmark = pytest.mark.skipif(not HAVE_CORE, reason="gi._core not built")


def stage(path, **settings):
    lines = [f'        custom {"string" if isinstance(v, str) else "int"} gi:{k.replace("__", ":")} = '
             f'{chr(34) + v + chr(34) if isinstance(v, str) else v}' for k, v in settings.items()]
    path.write_text("\n".join(['#usda 1.0', '(', f'    subLayers = [@{CORNELL}@]',
                               '    renderSettingsPrimPath = "/Render/Settings"', ')', '', 'over "Render"', '{',
                               '    over "Settings"', '    {', *lines, '    }', '}', '']))
    return path


def render(scene, out, *flags):
    result = run_gi("render", str(scene), "--resolution", "32", "32", "-o", str(out), "--no-png", *flags)
    from gi import _core
    _, metadata = _core.read_image(str(out))
    return metadata, result.stderr


def test_the_stage_settings_are_the_defaults_and_flags_win(tmp_path):
    scene = stage(tmp_path / "s.usda", integrator="direct", samples=3, seed=7, direct__lightSamples=2)
    meta, _ = render(scene, tmp_path / "a.exr")
    assert (meta["gi:integrator"], meta["gi:spp"], meta["gi:seed"]) == ("direct", "3", "7")
    assert '"lightSamples": 2' in meta["gi:params"]
    meta, _ = render(scene, tmp_path / "b.exr", "--spp", "2", "--seed", "1", "--light-samples", "4")
    assert (meta["gi:integrator"], meta["gi:spp"], meta["gi:seed"]) == ("direct", "2", "1")
    assert '"lightSamples": 4' in meta["gi:params"]
    meta, _ = render(scene, tmp_path / "c.exr", "--integrator", "path")
    assert meta["gi:integrator"] == "path" and meta["gi:spp"] == "3"
    # The stage's direct:lightSamples is not path's: not passed on to it.
    assert "lightSamples" not in meta["gi:params"]


def test_without_stage_settings_the_defaults_are_gi_renders(tmp_path):
    meta, _ = render(stage(tmp_path / "s.usda"), tmp_path / "a.exr")
    assert (meta["gi:integrator"], meta["gi:spp"], meta["gi:seed"]) == ("path", "16", "0")


def test_an_unknown_gi_setting_warns_naming_the_prim(tmp_path):
    _, stderr = render(stage(tmp_path / "s.usda", path__pathDepht=3), tmp_path / "a.exr")
    assert "/Render/Settings: unknown setting gi:path:pathDepht" in stderr
