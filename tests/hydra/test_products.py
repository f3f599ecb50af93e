"""UsdRender products through usdrecord (issue 20 item 1): with --renderSettingsPrimPath, hdGi
renders the product's camera at its resolution and writes the file its productName names, with
the declared RenderVars as named channels; `gi render` of the same stage writes the same file,
channel for channel and bit for bit (both follow renderer/render_vars.h), its data window too
(renderer/pixel_window.h); and usdrecord --frames names each frame's file by the productName's
frame tokens, as `gi render --frames` does."""
import subprocess

import numpy as np
import pytest

from conftest import CORNELL, REPO, hdgi_errors, run_openusd

SPP, SEED = 4, 0
VARS = {"Color": ("color", "color3f"), "Depth": ("depth", "float"), "N": ("normal", "normal3f"),
        "Albedo": ("albedo", "color3f"), "Bogus": ("specularIndirect", "color3f")}
EXPECTED_CHANNELS = ["R", "G", "B", "Depth", "Albedo.R", "Albedo.G", "Albedo.B", "N.X", "N.Y", "N.Z"]


def product_stage(path, product_files, window=None, resolution=None, seed=SEED, more="", attributes=None):
    """The Cornell box with one product of VARS per name in `product_files`, each with the
    dataWindowNDC `window` and the resolution `resolution` when given, or the attribute lines
    `attributes[i]` (USD text) instead; `more`: text added to the stage."""
    var_prims = "\n".join(f'''        def RenderVar "{name}"
        {{
            string sourceName = "{source}"
            token dataType = "{data_type}"
        }}''' for name, (source, data_type) in VARS.items())
    targets = ", ".join(f"</Render/Vars/{name}>" for name in VARS)
    common = (f"            uniform float4 dataWindowNDC = {tuple(window)}\n" if window else "") + \
             (f"            uniform int2 resolution = {tuple(resolution)}\n" if resolution else "")
    products = "\n".join(f'''        def RenderProduct "P{i}"
        {{
            token productName = "{name}"
{common if attributes is None else attributes[i]}            rel orderedVars = [{targets}]
        }}''' for i, name in enumerate(product_files))
    product_targets = ", ".join(f"</Render/Products/P{i}>" for i in range(len(product_files)))
    path.write_text(f'''#usda 1.0
(
    subLayers = [@{CORNELL}@]
    renderSettingsPrimPath = "/Render/Settings"
)

over "Render"
{{
    over "Settings"
    {{
        rel products = [{product_targets}]
        custom int gi:samples = {SPP}
        custom int gi:seed = {seed}
    }}
    def Scope "Products"
    {{
{products}
    }}
    def Scope "Vars"
    {{
{var_prims}
    }}
}}
{more}''')
    return path


def usdrecord(stage, output, *flags):
    """usdrecord with the stage's render settings; its log."""
    result = run_openusd(["usdrecord", "--disableGpu", "--renderer", "Gi", "--disableCameraLight",
                          "--colorCorrectionMode", "disabled", "--imageWidth", "128",
                          "--renderSettingsPrimPath", "/Render/Settings", *map(str, flags), str(stage), str(output)])
    log = result.stdout + result.stderr
    assert not hdgi_errors(log), log[-3000:]
    return log


def gi_render(stage, *flags):
    subprocess.run([str(REPO / ".venv/bin/gi"), "render", str(stage), "--spp", str(SPP), *map(str, flags)],
                   check=True, capture_output=True)


def read(path):
    from gi import _core
    pixels, metadata = _core.read_image(str(path))
    return np.asarray(pixels), metadata


# A window with edges inside pixels (0.6 x 512 = 307.2) and on pixel centres (xmin x 512 = 129.5,
# (1 - ymax) x 512 = 101.5: the low edges hold the centres they pass through, where rounding to
# the nearest pixel would not), and one reaching outside the image (clipped, with a warning). The
# pixels whose centres each holds (NDC y runs up: ymax gives the top row), worked out by hand.
WINDOWS = {"whole image": (None, (0, 0, 512, 512)),
           "window": ((129.5 / 512, 0.125, 0.6, 1 - 101.5 / 512), (129, 101, 307, 448)),
           "overscan": ((-0.5, 0.5, 0.5, 1.5), (0, 0, 256, 256))}


@pytest.mark.parametrize("window", WINDOWS)
def test_usdrecord_writes_the_declared_product_as_gi_render_does(tmp_path, window):
    (tmp_path / "hydra").mkdir()
    (tmp_path / "cli").mkdir()
    ndc, (x0, y0, x1, y1) = WINDOWS[window]
    hydra_stage = product_stage(tmp_path / "hydra/stage.usda", [tmp_path / "hydra/beauty.exr"], ndc)
    cli_stage = product_stage(tmp_path / "cli/stage.usda", [tmp_path / "cli/beauty.exr"], ndc)
    # usdrecord's own image (its viewport's size, 128 wide) is written only when no product was.
    log = usdrecord(hydra_stage, tmp_path / "hydra/usdrecord.exr")
    assert not (tmp_path / "hydra/usdrecord.exr").exists(), log[-3000:]
    assert "/Render/Vars/Bogus" in log and "specularIndirect" in log, log[-3000:]
    assert ("reaches outside the image" in log) == (window == "overscan"), log[-3000:]
    gi_render(cli_stage, "--seed", SEED)
    hydra, hydra_meta = read(tmp_path / "hydra/beauty.exr")
    cli, cli_meta = read(tmp_path / "cli/beauty.exr")
    # Bogus skipped; the beauty as plain R, G, B (the files list layers in EXR's name order).
    assert hydra_meta["channels"] == EXPECTED_CHANNELS and cli_meta["channels"] == EXPECTED_CHANNELS
    # The render settings' resolution (not usdrecord's width), the window's pixels only.
    assert hydra_meta["data_window"] == (x0, y0, x1 - x0, y1 - y0) == cli_meta["data_window"]
    assert hydra_meta["display_window"] == cli_meta["display_window"]
    assert hydra.shape == (y1 - y0, x1 - x0, len(EXPECTED_CHANNELS))
    assert hydra_meta["gi:product"] == "/Render/Products/P0"
    for c, name in enumerate(EXPECTED_CHANNELS):
        assert np.array_equal(hydra[..., c], cli[..., c]), name


# The glass sphere moves from x = -0.4 on frame 1 to 0.4 on frame 2.
MOVING_SPHERE = """
over "World"
{
    over "GlassSphere"
    {
        double3 xformOp:translate.timeSamples = {1: (-0.4, -0.6, 0), 2: (0.4, -0.6, 0)}
    }
}
"""


def test_usdrecord_frames_write_one_file_per_frame_named_by_the_frame_tokens(tmp_path):
    """usdrecord --frames 1:3 sets the scene globals' current frame, which names each frame's files
    (#### and $F4 zero-padded, $F not), and each equals `gi render --frames` of that frame bit for
    bit. Frame 3 shows what frame 2 does (the sphere's last sample), so nothing in the scene
    changes: its files are written all the same. Both hosts seed frame f with seed + f
    (renderer/render_vars.h's frameSeed), so both render with --seed 3."""
    names = ["beauty.####.exr", "beauty.$F4.exr", "beauty.$F.exr"]
    for host in ("hydra", "cli"):
        (tmp_path / host).mkdir()
    hydra_stage = product_stage(tmp_path / "hydra/stage.usda", [tmp_path / "hydra" / n for n in names],
                                resolution=(96, 96), seed=3, more=MOVING_SPHERE)
    cli_stage = product_stage(tmp_path / "cli/stage.usda", [tmp_path / "cli" / n for n in names],
                              resolution=(96, 96), more=MOVING_SPHERE)
    log = usdrecord(hydra_stage, tmp_path / "hydra/usdrecord.#.exr", "--frames", "1:3")
    assert "frame tokens" not in log, log[-3000:]
    written = sorted(p.name for p in (tmp_path / "hydra").glob("beauty.*"))
    files = ["beauty.0001.exr", "beauty.0002.exr", "beauty.0003.exr", "beauty.1.exr", "beauty.2.exr", "beauty.3.exr"]
    assert written == files, written
    for frame in (1, 2, 3):
        gi_render(cli_stage, "--frames", frame, "--seed", 3)
    frames = {}
    for name in files:
        hydra, meta = read(tmp_path / "hydra" / name)
        cli, _ = read(tmp_path / "cli" / name)
        assert meta["gi:frame"] == name.split(".")[1].lstrip("0"), meta
        assert np.array_equal(hydra, cli), name
        frames[name] = hydra
    # Each frame's files hold that frame: the sphere moved between them.
    assert np.array_equal(frames["beauty.0001.exr"], frames["beauty.1.exr"])
    assert not np.array_equal(frames["beauty.0001.exr"], frames["beauty.0002.exr"])


def test_usdrecord_frames_of_a_still_scene_write_every_frame(tmp_path):
    """Nothing on the stage varies in time, so no prim changes between frames: each frame's file is
    written all the same (the frame restarts the render), seeded seed + frame as `gi render --frames`
    seeds it, so the two frames differ only in their noise."""
    stage = product_stage(tmp_path / "stage.usda", [tmp_path / "still.$F.exr"], resolution=(32, 32))
    usdrecord(stage, tmp_path / "usdrecord.#.exr", "--frames", "1:2")
    first, first_meta = read(tmp_path / "still.1.exr")
    second, second_meta = read(tmp_path / "still.2.exr")
    assert (first_meta["gi:frame"], second_meta["gi:frame"]) == ("1", "2")
    assert (first_meta["gi:seed"], second_meta["gi:seed"]) == (str(SEED + 1), str(SEED + 2))
    assert not np.array_equal(first, second)
    assert abs(first[..., :3].mean() / second[..., :3].mean() - 1) < 0.2  # the same scene


SIDE_CAMERA = """
over "World"
{
    def Camera "Side"
    {
        float focalLength = 35
        float horizontalAperture = 36
        float verticalAperture = 24
        float2 clippingRange = (0.01, 100)
        double3 xformOp:translate = (0.4, 0.1, 3.6)
        float3 xformOp:rotateXYZ = (2, 6, 0)
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateXYZ"]
    }
}
"""

# Three products of one render settings prim: the settings' camera at 64 x 64; another camera at
# 72 x 48 with a data window and a conform policy of its own; and the first again under another
# name (the two share one render in Hydra). Name -> attribute lines.
PRODUCTS = {"front": "            uniform int2 resolution = (64, 64)\n",
            "side": "            rel camera = </World/Side>\n"
                    "            uniform int2 resolution = (72, 48)\n"
                    "            uniform float4 dataWindowNDC = (0.25, 0, 1, 0.75)\n"
                    '            uniform token aspectRatioConformPolicy = "cropAperture"\n',
            "front_again": "            uniform int2 resolution = (64, 64)\n"}


def products_stage(path, folder):
    return product_stage(path, [folder / f"{name}.exr" for name in PRODUCTS], more=SIDE_CAMERA,
                         attributes=list(PRODUCTS.values()))


def test_usdrecord_renders_each_products_own_camera_resolution_and_window(tmp_path):
    """Products of one render settings prim with different cameras, resolutions, conform policies
    and data windows: hdGi renders one image per distinct set, in turn, and each file equals what
    `gi render` writes for that product, channel for channel and bit for bit."""
    for host in ("hydra", "cli"):
        (tmp_path / host).mkdir()
    log = usdrecord(products_stage(tmp_path / "hydra/stage.usda", tmp_path / "hydra"), tmp_path / "hydra/usdrecord.exr")
    assert "differs from the first product's" not in log and "is not the render's" not in log, log[-3000:]
    gi_render(products_stage(tmp_path / "cli/stage.usda", tmp_path / "cli"), "--seed", SEED)
    images = {}
    for name in PRODUCTS:
        hydra, hydra_meta = read(tmp_path / "hydra" / f"{name}.exr")
        cli, cli_meta = read(tmp_path / "cli" / f"{name}.exr")
        assert hydra_meta["channels"] == EXPECTED_CHANNELS == cli_meta["channels"], name
        assert hydra_meta["data_window"] == cli_meta["data_window"], name
        assert hydra_meta["display_window"] == cli_meta["display_window"], name
        assert hydra_meta["gi:product"] == f"/Render/Products/P{list(PRODUCTS).index(name)}"
        assert np.array_equal(hydra, cli), name
        images[name] = (hydra, hydra_meta)
    # 72 x 48 with the window's pixels only: x from 18 to 72, the bottom three quarters of the rows
    # (NDC y runs up).
    assert images["side"][1]["data_window"] == (18, 12, 54, 36)
    assert images["front"][0].shape[:2] == (64, 64)
    assert np.array_equal(images["front"][0], images["front_again"][0])
