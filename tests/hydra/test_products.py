"""UsdRender products through usdrecord (issue 20 item 1): with --renderSettingsPrimPath, hdGi
renders the product's camera at its resolution and writes the file its productName names, with
the declared RenderVars as named channels; `gi render` of the same stage writes the same file,
channel for channel and bit for bit (both follow renderer/render_vars.h)."""
import subprocess

import numpy as np

from conftest import CORNELL, REPO, run_openusd

SPP, SEED = 4, 0
VARS = {"Color": ("color", "color3f"), "Depth": ("depth", "float"), "N": ("normal", "normal3f"),
        "Albedo": ("albedo", "color3f"), "Bogus": ("specularIndirect", "color3f")}


def product_stage(path, product_file):
    var_prims = "\n".join(f'''        def RenderVar "{name}"
        {{
            string sourceName = "{source}"
            token dataType = "{data_type}"
        }}''' for name, (source, data_type) in VARS.items())
    targets = ", ".join(f"</Render/Vars/{name}>" for name in VARS)
    path.write_text(f'''#usda 1.0
(
    subLayers = [@{CORNELL}@]
    renderSettingsPrimPath = "/Render/Settings"
)

over "Render"
{{
    over "Settings"
    {{
        rel products = </Render/Products/Beauty>
        custom int gi:samples = {SPP}
        custom int gi:seed = {SEED}
    }}
    def Scope "Products"
    {{
        def RenderProduct "Beauty"
        {{
            token productName = "{product_file}"
            rel orderedVars = [{targets}]
        }}
    }}
    def Scope "Vars"
    {{
{var_prims}
    }}
}}
''')
    return path


def read(path):
    from gi import _core
    pixels, metadata = _core.read_image(str(path))
    return np.asarray(pixels), metadata


def test_usdrecord_writes_the_declared_product_as_gi_render_does(tmp_path):
    (tmp_path / "hydra").mkdir()
    (tmp_path / "cli").mkdir()
    hydra_stage = product_stage(tmp_path / "hydra/stage.usda", tmp_path / "hydra/beauty.exr")
    cli_stage = product_stage(tmp_path / "cli/stage.usda", tmp_path / "cli/beauty.exr")
    # usdrecord's own image (its viewport's size, 128 wide) is written only when no product was.
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--colorCorrectionMode", "disabled", "--imageWidth", "128",
                          "--renderSettingsPrimPath", "/Render/Settings", str(hydra_stage),
                          str(tmp_path / "hydra/usdrecord.exr")])
    log = result.stdout + result.stderr
    assert not (tmp_path / "hydra/usdrecord.exr").exists(), log[-3000:]
    assert "/Render/Vars/Bogus" in log and "specularIndirect" in log, log[-3000:]
    subprocess.run([str(REPO / ".venv/bin/gi"), "render", str(cli_stage), "--spp", str(SPP), "--seed", str(SEED)],
                   check=True, capture_output=True)
    hydra, hydra_meta = read(tmp_path / "hydra/beauty.exr")
    cli, cli_meta = read(tmp_path / "cli/beauty.exr")
    # Bogus skipped; the beauty as plain R, G, B (the files list layers in EXR's name order).
    expected = ["R", "G", "B", "Depth", "Albedo.R", "Albedo.G", "Albedo.B", "N.X", "N.Y", "N.Z"]
    assert hydra_meta["channels"] == expected and cli_meta["channels"] == expected
    assert hydra.shape == (512, 512, len(expected))  # the render settings' resolution, not usdrecord's width
    assert hydra_meta["gi:product"] == "/Render/Products/Beauty"
    for c, name in enumerate(expected):
        assert np.array_equal(hydra[..., c], cli[..., c]), name
