"""`gi render`: the frames (gi.sequence) times the images each frame writes (the -o EXR, or the
render settings' RenderProducts, gi.products), rendered and written with one summary line each."""
import datetime
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from . import __version__
from .errors import warn
from .render import (COMPLEXITY_REFINE_LEVELS, DEFAULT_COMPLEXITY, progress_bar, render_loaded, render_settings,
                     require_core)


def check_frame_names(args, parser, pattern, flag):
    from .frames import has_frame_token
    if args.frames and len(args.frames) > 1 and not has_frame_token(pattern):
        parser.error(f"{flag} {pattern} names one file but --frames renders {len(args.frames)} frames; put #### or "
                     f"$F4 in it (e.g. out/shot.####.exr)")


@dataclass
class Target:
    """One image a frame renders: the -o (or default) EXR, or a RenderProduct."""
    exr: str                  # path pattern (frame tokens not substituted)
    product: object = None    # gi.products.Product, or None for the default layers
    resolution: tuple = None  # None: --resolution, else the loaded scene's
    camera: str = ""          # a camera prim path other than the loaded scene's, or ''
    window: tuple = None      # (x0, y0, x1, y1) pixels, or None for the whole image


def render_targets(args, parser, sequence):
    """Without -o (and --tile), the render settings' RenderProducts; else the one -o EXR."""
    from .loader import as_time_code
    from .products import pixel_window, read_products, settings_prim
    if not args.output and not args.tile:
        settings = settings_prim(sequence.stage, args.settings, sequence.path)
        products = read_products(sequence.stage, settings, as_time_code(sequence.frames[0]), args.camera, lambda path, message: warn(f"{sequence.path}: {path}: {message}"))
        targets = []
        for product in products:
            check_frame_names(args, parser, product.name, f"{product.path} productName")
            resolution = tuple(args.resolution) if args.resolution else product.resolution
            product.resolution = resolution
            window = pixel_window(product, lambda path, message: warn(f"{sequence.path}: {path}: {message}"))
            targets.append(Target(product.name, product, resolution, product.camera, window))
        if targets:
            return targets
    elif args.settings:
        parser.error("--settings picks the RenderProducts to write; -o and --tile write one image instead")
    default = str(Path("out") / f"{Path(args.scene).stem}{'.####' if args.frames else ''}.exr")
    exr = args.output or default
    check_frame_names(args, parser, exr, "-o")
    return [Target(exr)]


def write_target(target, result, metadata, args, number, denoised=None):
    """Writes the target's EXR (and the default target's PNG); returns the paths written.
    denoised: the denoised colour, written as the default target's R, G, B and PNG, with the raw
    colour as its noisy.R/G/B layer."""
    from .frames import frame_path
    _core = require_core()
    exr = Path(frame_path(target.exr, number))
    exr.parent.mkdir(parents=True, exist_ok=True)
    if target.product is not None:
        from .products import product_planes
        pixels, channels, half = product_planes(target.product, result)
        x0, y0, x1, y1 = result.data_window
        metadata["gi:product"] = target.product.path
        full = (x1 - x0, y1 - y0) == tuple(target.resolution)
        _core.write_channels_exr(str(exr), pixels, channels, metadata,
                                 None if full else (x0, y0, *target.resolution), half)
        return [str(exr)]
    color = result.color if denoised is None else denoised
    _core.write_exr(str(exr), result, metadata, color=color, layers={} if denoised is None else {"noisy": result.color})
    outputs = [str(exr)]
    if not args.no_png and not args.tile:  # a tile's picture is written by the merge
        png = Path(frame_path(args.png, number)) if args.png else exr.with_suffix(".png")
        png.parent.mkdir(parents=True, exist_ok=True)
        _core.write_png(str(png), color, args.display, args.view, args.exposure)
        outputs.append(str(png))
    return outputs


def name_number(frame, sequence):
    """The number a frame token takes: the frame, or without --frames the earliest time sample
    (the time rendered then), 0 on a stage with none."""
    if frame is not None:
        return frame
    return int(sequence.time_range[0]) if sequence.time_range else 0


# What `gi render` uses when neither a flag nor the stage's render settings say.
RENDER_DEFAULTS = {"integrator": "path", "spp": 16, "seed": 0, "time_limit": 0.0, "preset": None}


def apply_stage_settings(args, sequence):
    """Fills the render flags not given with the render settings prim's gi: settings (as hdGi
    reads them), else RENDER_DEFAULTS; returns the stage's integrator parameters
    ({integrator: {parameter: value}}), which the flags given override."""
    from .products import settings_prim
    from .render import integrator_catalog
    from .stage_settings import read_stage_settings
    settings = settings_prim(sequence.stage, args.settings, sequence.path)
    found = read_stage_settings(settings, integrator_catalog(), lambda message: warn(f"{sequence.path}: {message}"))
    for dest, default in RENDER_DEFAULTS.items():
        if getattr(args, dest) is None:
            setattr(args, dest, found.values.get(dest, default))
    return found.params


def cmd_render(args, flags, parser):
    from .frames import frame_seed
    from .loader import camera_at
    from .sequence import Sequence
    from .tiles import tile_window, why_tiles_differ
    frames = args.frames or [None]
    sequence = Sequence(args.scene, frames, camera=args.camera, allow_missing=args.allow_missing,
                        refine_level=COMPLEXITY_REFINE_LEVELS[args.complexity], purposes=args.purposes)
    for message in sequence.warnings:
        warn(message)
    stage_params = apply_stage_settings(args, sequence)
    params = {**stage_params.get(args.integrator, {}), **flags.chosen(args, parser)}
    if args.tile and why_tiles_differ(args):
        parser.error(f"--tile with {why_tiles_differ(args)}")
    denoiser = None
    if args.denoise:  # before rendering: a missing denoiser must not cost a render first
        from .denoise import open_denoiser
        denoiser = open_denoiser(args.threads)
    targets = render_targets(args, parser, sequence)
    if denoiser is not None and any(target.product is not None for target in targets):
        warn("--denoise denoises the -o image; the RenderProducts are written undenoised")
    label = f"{Path(args.scene).name} [{args.integrator}]"
    bar, update = progress_bar(f"{label} {len(frames)} frames" if args.frames else label, sys.stderr.isatty())
    warned = set()  # each load's warnings once, not once per frame
    # auto: the first render's choice renders every later frame and target (no pilots), so that a
    # sequence does not switch between techniques (RenderSettings::keptAutoChoice).
    kept_choice = ""
    steps = len(frames) * len(targets)
    start = time.perf_counter()  # each frame's time counts its load (done as the sequence advances)
    try:
        for index, frame in enumerate(sequence):
            for message in frame.loaded.warnings:
                if message not in warned:
                    warned.add(message)
                    warn(message)
            # Frame F renders with seed + F; without --frames, F is the stage's start time code, the
            # frame usdrecord renders then (0 where none is authored).
            seed = frame_seed(args.seed, frame.number if frame.number is not None else sequence.stage.GetStartTimeCode())
            for t, target in enumerate(targets):
                settings = render_settings(frame.loaded, args.integrator, params, args.spp, seed, args.threads,
                                           args.time_limit,
                                           target.resolution or (tuple(args.resolution) if args.resolution else None),
                                           args.filter)
                settings.preset = args.preset or ""
                settings.kept_auto_choice = kept_choice
                if target.product is not None:
                    settings.aspect_ratio_conform_policy, settings.pixel_aspect_ratio = target.product.framing
                if args.tile:
                    settings.data_window = tile_window(args.tile, settings.width, settings.height)
                elif target.window:
                    settings.data_window = target.window
                camera = frame.camera
                if target.camera and target.camera != frame.loaded.camera_path:
                    camera = camera_at(sequence.stage, target.camera, frame.number)
                step = index * len(targets) + t
                result = render_loaded(frame.loaded, settings, label, camera=camera,
                                       progress=lambda fraction: update((step + fraction) / steps))
                wall_seconds = time.perf_counter() - start
                for message in frame.loaded.scene.warnings():
                    if message not in warned:
                        warned.add(message)
                        warn(f"{sequence.path}: {message}")
                if result.auto_summary:
                    print(f"gi: {result.auto_summary}", file=sys.stderr)
                if args.integrator == "auto":
                    kept_choice = result.integrator
                metadata = exr_metadata(args, params, result, frame.loaded, wall_seconds, frame.number, seed)
                denoised, denoised_text = None, ""
                if denoiser is not None and target.product is None:
                    from .denoise import denoise_metadata, denoise_result
                    denoised, denoise_seconds = denoise_result(denoiser, result)
                    metadata.update(denoise_metadata(denoiser, denoise_seconds))
                    denoised_text = f", denoised in {denoise_seconds:.2f} s (OIDN {denoiser.version})"
                if target.camera:
                    metadata["gi:camera"] = target.camera
                if args.tile:
                    metadata["gi:tile"] = args.tile.text
                outputs = write_target(target, result, metadata, args, name_number(frame.number, sequence), denoised)
                bar.clear()
                print(summary(args, settings, result, wall_seconds, outputs, frame.number) + denoised_text +
                      (scene_note(frame) if args.frames and t == 0 else ""), flush=True)
                start = time.perf_counter()
    finally:
        bar.close()
    return 0


def exr_metadata(args, params, result, loaded, wall_seconds, frame=None, seed=None):
    """String attributes that make the EXR reproducible: what rendered it, how, and when."""
    return {"gi:version": __version__, "gi:scene": str(args.scene), "gi:camera": loaded.camera_path,
            "gi:integrator": result.integrator or args.integrator, "gi:auto": result.auto_summary,
            "gi:spp": str(result.spp), "gi:seed": str(args.seed if seed is None else seed),
            "gi:complexity": getattr(args, "complexity", DEFAULT_COMPLEXITY),
            "gi:frame": "earliest time" if frame is None else str(frame),
            "gi:params": json.dumps(params, sort_keys=True), "gi:preset": args.preset or "",
            "gi:seconds": f"{result.stats.get('seconds', wall_seconds):.3f}",
            "gi:wall_seconds": f"{wall_seconds:.3f}",
            # Samples the renderer replaced (NaN, Inf, negative): the pixels never show them.
            "gi:non_finite_samples": str(int(result.stats["non_finite_samples"])),
            "gi:date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")}


def scene_note(frame):
    """What a frame of a sequence built: its BVH work, or nothing (the previous frame's scene)."""
    if not frame.rebuilt:
        return "; scene of the previous frame"
    stats = frame.loaded.scene.stats()
    return (f"; scene built in {stats.get('build_seconds', 0):.3f} s (BVH: {int(stats.get('primitives_built', 0)):,} "
            f"primitives built, {int(stats.get('primitives_reused', 0)):,} kept from the previous frame)")


def summary(args, settings, result, wall_seconds, outputs, frame=None):
    stats = result.stats
    x0, y0, x1, y1 = result.data_window
    size = f"{settings.width}x{settings.height}" + (
        f" (data window {x1 - x0}x{y1 - y0} at {x0},{y0})" if (x1 - x0, y1 - y0) != (settings.width, settings.height) else "")
    technique = args.integrator if result.integrator in ("", args.integrator) else \
        f"{args.integrator} -> {result.integrator}"
    return (f"{args.scene}{'' if frame is None else f' frame {frame}'}: {size} {technique} "
            f"{result.spp} spp in {wall_seconds:.2f} s, {stats.get('rays_per_second', 0) / 1e6:.2f} Mrays/s, "
            f"{stats.get('samples_per_second', 0) / 1e3:.1f} ksamples/s -> {', '.join(outputs)}")
