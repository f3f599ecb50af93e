"""The parity stages as the tests render them: a stage copied into a scratch folder with the tiny
textures it names written beside it (generated here, so no image is committed).

quadrants.exr: 2 x 2 texels, linear float RGB. USD's st has v = 0 at the bottom, so with wrap
clamp st (0.25, 0.25) reads the bottom-left texel exactly, (0.75, 0.75) the top-right one."""
import shutil
from pathlib import Path

import numpy as np

PARITY = Path(__file__).resolve().parent

RED, GREEN, BLUE, WHITE = (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)
# Texel colour at the centre of each quarter of st space: (u, v) -> colour.
QUADRANTS = {(0.25, 0.25): RED, (0.75, 0.25): GREEN, (0.25, 0.75): BLUE, (0.75, 0.75): WHITE}


def quadrants_texture():
    """QUADRANTS as an image, top row first."""
    return np.array([[BLUE, WHITE], [RED, GREEN]], np.float32)


TEXTURES = {"quadrants.exr": quadrants_texture}
# UDIM sets: pattern -> {tile: its one colour}; each tile 2 x 2 texels (texture_udim.usda).
UDIM_TILES = {"tiles.<UDIM>.exr": {1001: RED, 1002: GREEN, 1011: BLUE}}
UDIM_FALLBACK = (0.5, 0.5, 0.5)


def prepare(stage, directory, absolute_udim=False):
    """tests/parity/<stage>.usda copied into `directory` with the textures it names; its new path.
    absolute_udim: its UDIM patterns made absolute paths (Hydra's scene index in OpenUSD 24.11
    hands a relative one over unanchored)."""
    from gi import _core
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    source = PARITY / f"{stage}.usda"
    target = directory / source.name
    shutil.copyfile(source, target)
    text = source.read_text()
    for name, pixels in TEXTURES.items():
        if f"@{name}@" in text:
            _core.write_rgb_exr(str(directory / name), np.ascontiguousarray(pixels()))
    for pattern, tiles in UDIM_TILES.items():
        if f"@{pattern}@" in text and absolute_udim:
            target.write_text(target.read_text().replace(f"@{pattern}@", f"@{(directory / pattern).resolve()}@"))
        if f"@{pattern}@" in text:
            for tile, colour in tiles.items():
                _core.write_rgb_exr(str(directory / pattern.replace("<UDIM>", str(tile))),
                                    np.full((2, 2, 3), colour, np.float32))
    return target


# camera_conform.usda's render settings overridden: (aspectRatioConformPolicy, pixelAspectRatio).
CONFORM_CASES = [("cropAperture", 1.0), ("adjustApertureWidth", 0.5), ("adjustApertureHeight", 0.5),
                 ("adjustPixelAspectRatio", 1.0), ("expandAperture", 0.5)]


# What the settings say when a product carries the case (each case differs from it): a host taking
# the settings' framing instead of the product's would render a window four times as wide as tall.
SETTINGS_DECOY = ("adjustApertureWidth", 2.0)


def conform_layer(path, stage, policy, pixel_aspect, product=None, settings="", inherited=False):
    """A layer over `stage` (a prepared camera_conform.usda) framed by `policy` and `pixel_aspect`.
    Without `product` the render settings carry them. With `product` (a file path) the settings
    declare one RenderProduct written there, which carries them while the settings say
    SETTINGS_DECOY (the product's own values win over its settings'), or, `inherited`, which
    authors none and inherits them from the settings, which carry them. It holds the beauty and the
    depth (which follows each ray's direction to its last bits, where the beauty, a covered
    fraction, rarely changes). Products are what make usdrecord render the settings' resolution
    and framing. `settings`: more lines for the settings prim (gi:* attributes). Returns `path`."""
    framing = f"""uniform token aspectRatioConformPolicy = "{policy}"
        uniform float pixelAspectRatio = {pixel_aspect!r}"""
    settings_framing, product_lines = framing, ""
    if product is not None and inherited:
        settings_framing, framing = framing + "\n        rel products = </Render/Image>", ""
    elif product is not None:
        settings_framing = f"""uniform token aspectRatioConformPolicy = "{SETTINGS_DECOY[0]}"
        uniform float pixelAspectRatio = {SETTINGS_DECOY[1]!r}
        rel products = </Render/Image>"""
    if product is not None:
        product_lines = f'''
    def RenderProduct "Image"
    {{
        token productName = "{product}"
        {framing}
        rel orderedVars = [</Render/Color>, </Render/Depth>]
    }}
    def RenderVar "Color"
    {{
        string sourceName = "color"
        token dataType = "color3f"
    }}
    def RenderVar "Depth"
    {{
        string sourceName = "depth"
        token dataType = "float"
    }}'''
    Path(path).write_text(f'''#usda 1.0
(
    subLayers = [@{Path(stage).resolve()}@]
    renderSettingsPrimPath = "/Render/Settings"
)

over "Render"
{{
    over "Settings"
    {{
        {settings_framing}
        {settings}
    }}{product_lines}
}}
''')
    return Path(path)
