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


def prepare(stage, directory):
    """tests/parity/<stage>.usda copied into `directory` with the textures it names; its new path."""
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
    return target
