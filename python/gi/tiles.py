"""Tiles of a frame: `gi render --tile CxR:I` renders one (an EXR whose data window is the tile),
`gi merge-tiles` joins a frame's tiles into the whole image.

Each pixel's samples depend only on its position, the sample index and the seed, and a tile is
rendered with the whole image's camera, passes and preprocessing (renderer/render.h, PixelWindow),
so the merged image equals the whole-frame render bit for bit, for every integrator: the caches
and photon maps are built from the whole image in every tile (their preprocessing is repeated per
tile, which is what a tile costs beyond its share of the sampling)."""
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

TILE = re.compile(r"^\s*(\d+)\s*x\s*(\d+)\s*(?::\s*(\d+))?\s*$")
TILE_TOKEN = "{tile}"


@dataclass(frozen=True)
class Tiling:
    columns: int
    rows: int
    index: int = None  # one tile of the tiling (row by row from the top left), or None for all

    @property
    def count(self):
        return self.columns * self.rows

    @property
    def text(self):
        grid = f"{self.columns}x{self.rows}"
        return grid if self.index is None else f"{grid}:{self.index}"


def parse_tile(text, with_index=True):
    """'2x2:3' (with_index) or '2x2' -> Tiling; ValueError saying what is wrong."""
    match = TILE.match(text)
    if not match or (match.group(3) is None) == with_index:
        form = "CxR:I, e.g. 2x2:3" if with_index else "CxR, e.g. 2x2"
        raise ValueError(f"{text!r} is not a tile ({form})")
    columns, rows = int(match.group(1)), int(match.group(2))
    if columns < 1 or rows < 1:
        raise ValueError(f"{text!r}: a tiling needs at least one column and one row")
    index = int(match.group(3)) if with_index else None
    if index is not None and index >= columns * rows:
        raise ValueError(f"{text!r}: tile {index} does not exist (a {columns}x{rows} tiling has tiles "
                         f"0..{columns * rows - 1})")
    return Tiling(columns, rows, index)


def why_tiles_differ(render):
    """Why the tiles of a `gi render` with these options would not join into its whole frame, or ''."""
    if render.time_limit:
        return "--time-limit: a time-limited render stops where the clock says, so its tiles would not join " \
               "into one image; give --spp instead"
    if render.integrator == "auto":
        return "--integrator auto: auto chooses a technique per render from measured pilot timings, so tiles " \
               "could differ; give the integrator it chooses (gi render --integrator auto says)"
    if getattr(render, "denoise", False):
        return "--denoise: the denoiser filters across pixels, so tiles denoised apart would not join into the " \
               "denoised frame; denoise whole frames"
    return ""


def tile_window(tiling, width, height):
    """(x0, y0, x1, y1) of the tile in a width x height image. ValueError when the image has fewer
    pixels than the tiling has columns or rows."""
    if tiling.columns > width or tiling.rows > height:
        raise ValueError(f"--tile {tiling.text}: a {width}x{height} image cannot be cut into "
                         f"{tiling.columns}x{tiling.rows} tiles")
    column, row = tiling.index % tiling.columns, tiling.index // tiling.columns
    return (width * column // tiling.columns, height * row // tiling.rows,
            width * (column + 1) // tiling.columns, height * (row + 1) // tiling.rows)


def tile_path(pattern, index):
    return str(pattern).replace(TILE_TOKEN, str(index))


def merge(tile_files, out_exr):
    """Joins tile EXRs (each a data window of the same image, as `gi render --tile` writes them) into
    one whole-image EXR with the same channels. The tiles must cover the image exactly once.
    Returns the merged (H, W, C) pixels and channel names; ValueError naming the file at fault."""
    from . import _core
    image = covered = channels = metadata = None
    for file in tile_files:
        if not Path(file).exists():
            raise ValueError(f"{file}: missing tile (did its task fail?)")
        pixels, meta = _core.read_image(str(file))
        x, y, w, h = meta["data_window"]
        full_width, full_height = meta["display_window"]
        if image is None:
            image = np.zeros((full_height, full_width, pixels.shape[2]), np.float32)
            covered = np.zeros((full_height, full_width), np.int32)
            channels = meta["channels"]
            metadata = {k: v for k, v in meta.items() if k.startswith("gi:") and k not in
                        ("gi:tile", "gi:seconds", "gi:wall_seconds", "gi:date")}
        elif image.shape[:2] != (full_height, full_width) or meta["channels"] != channels:
            raise ValueError(f"{file}: a tile of another image ({full_width}x{full_height}, channels "
                             f"{','.join(meta['channels'])}; the first tile's: {image.shape[1]}x{image.shape[0]}, "
                             f"{','.join(channels)})")
        if x < 0 or y < 0 or x + w > full_width or y + h > full_height:
            raise ValueError(f"{file}: data window {w}x{h} at {x},{y} is outside the {full_width}x{full_height} image")
        image[y:y + h, x:x + w] = pixels
        covered[y:y + h, x:x + w] += 1
    if image is None:
        raise ValueError("no tiles to merge")
    if (covered != 1).any():
        ys, xs = np.nonzero(covered != 1)
        raise ValueError(f"{out_exr}: the tiles {'overlap' if covered.max() > 1 else 'leave gaps'} "
                         f"(e.g. pixel {xs[0]},{ys[0]} is in {covered[ys[0], xs[0]]} tiles)")
    metadata["gi:tiles"] = str(len(tile_files))
    Path(out_exr).parent.mkdir(parents=True, exist_ok=True)
    _core.write_channels_exr(str(out_exr), image, channels, metadata)
    return image, channels


def cmd_merge_tiles(args):
    from .frames import frame_path
    for frame in args.frames:
        out = frame_path(args.output, frame)
        files = [frame_path(tile_path(args.tiles_pattern, i), frame) for i in range(args.tiles.count)]
        image, channels = merge(files, out)
        outputs = [out]
        if not args.no_png:
            from . import _core
            png = str(Path(out).with_suffix(".png"))
            _core.write_png(png, np.ascontiguousarray(image[..., :3]))
            outputs.append(png)
        print(f"frame {frame}: {len(files)} tiles -> {', '.join(outputs)}", flush=True)
    return 0
