"""The `gi` command: render, inspect (and, as they land, reference/study/import)."""
import argparse
import json
import re
import sys
import time
from pathlib import Path

from .errors import SceneError


def kebab(name):
    """pathDepth -> path-depth"""
    return re.sub(r"(?<!^)(?=[A-Z])", "-", name).lower()


def integrator_params():
    """{param name: param info} over every integrator, and {integrator: its param names}."""
    from . import _core
    params, owners = {}, {}
    for info in _core.integrators():
        owners[info["name"]] = {p["name"] for p in info["params"]}
        for p in info["params"]:
            params.setdefault(p["name"], p)
    return params, owners


def add_integrator_flags(parser):
    params, owners = integrator_params()
    group = parser.add_argument_group("integrator parameters (generated from each integrator's parameter list)")
    types = {"int": int, "float": float, "bool": lambda s: s.lower() in ("1", "true", "yes", "on")}
    for name, p in sorted(params.items()):
        users = ", ".join(sorted(i for i, names in owners.items() if name in names))
        group.add_argument(f"--{kebab(name)}", dest=f"param_{name}", type=types[p["type"]], default=None,
                           metavar=p["type"].upper(),
                           help=f"{p['description']} (default {p['default']}, range {p['min']}..{p['max']}; {users})")
    parser.add_argument("--integrator", default="path", choices=sorted(owners),
                        help="light transport technique (default: path)")
    return owners


def chosen_params(args, owners):
    """The integrator parameters given on the command line; warns about ones it does not take."""
    given = {k[len("param_"):]: v for k, v in vars(args).items() if k.startswith("param_") and v is not None}
    for name in sorted(set(given) - owners[args.integrator]):
        print(f"gi: warning: --{kebab(name)} is not a parameter of '{args.integrator}'; ignored", file=sys.stderr)
    return {k: v for k, v in given.items() if k in owners[args.integrator]}


def progress_bar(description, enabled):
    from tqdm import tqdm
    bar = tqdm(total=1000, desc=description, unit="‰", disable=not enabled, leave=False,
               bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}<{remaining}")
    def update(fraction):
        bar.n = int(fraction * 1000)
        bar.refresh()
    return bar, update


def render_scene(scene_path, integrator="path", params=None, spp=16, seed=0, threads=0, time_limit=0.0,
                 resolution=None, camera=None, show_progress=False, filter="box"):
    """Loads and renders a scene; returns (result, loaded scene, settings). Used by every command."""
    from . import _core
    from .loader import load_stage
    loaded = load_stage(scene_path, camera=camera)
    settings = _core.RenderSettings()
    settings.width, settings.height = resolution or loaded.resolution
    settings.spp = spp
    settings.integrator = integrator
    settings.params = dict(params or {})
    settings.seed = seed
    settings.threads = threads
    settings.time_limit = time_limit
    settings.filter = filter
    bar, update = progress_bar(f"{Path(scene_path).name} [{integrator}]", show_progress)
    try:
        result = _core.render(loaded.scene, settings, update)
    finally:
        bar.close()
    return result, loaded, settings


def cmd_render(args, owners):
    from . import _core
    params = chosen_params(args, owners)
    start = time.perf_counter()
    result, loaded, settings = render_scene(
        args.scene, args.integrator, params, args.spp, args.seed, args.threads, args.time_limit,
        tuple(args.resolution) if args.resolution else None, args.camera, sys.stderr.isatty(), args.filter)
    wall = time.perf_counter() - start
    for warning in loaded.warnings + loaded.scene.warnings():
        print(f"gi: warning: {warning}", file=sys.stderr)
    out = Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    metadata = {"gi:integrator": args.integrator, "gi:spp": str(result.spp), "gi:seed": str(args.seed),
                "gi:params": json.dumps(params, sort_keys=True), "gi:scene": str(args.scene),
                "gi:camera": loaded.camera_path, "gi:seconds": f"{result.stats['seconds']:.3f}"}
    _core.write_exr(str(out), result, metadata)
    outputs = [str(out)]
    if not args.no_png:
        png = Path(args.png) if args.png else out.with_suffix(".png")
        _core.write_png(str(png), result.color, args.display, args.view, args.exposure)
        outputs.append(str(png))
    s = result.stats
    print(f"{args.scene}: {settings.width}x{settings.height} {args.integrator} {result.spp} spp in {wall:.2f} s "
          f"(render {s['render_seconds']:.2f} s, preprocess {s['preprocess_seconds']:.2f} s), "
          f"{s['rays_per_second'] / 1e6:.2f} Mrays/s, {s['samples_per_second'] / 1e3:.1f} ksamples/s, "
          f"peak {s['peak_memory_bytes'] / 2**20:.0f} MiB -> {', '.join(outputs)}")
    return 0


def cmd_inspect(args):
    from .inspect import inspect_scene, format_report
    print(format_report(inspect_scene(args.scene)))
    return 0


def build_parser():
    parser = argparse.ArgumentParser(prog="gi", description="hdGi: CPU global illumination for USD scenes")
    sub = parser.add_subparsers(dest="command", required=True)
    render = sub.add_parser("render", help="render a USD scene to a linear EXR and a display PNG")
    render.add_argument("scene")
    render.add_argument("-o", "--output", default="out/render.exr", help="EXR path (default out/render.exr)")
    render.add_argument("--spp", type=int, default=16, help="camera samples per pixel (default 16)")
    render.add_argument("--seed", type=int, default=0)
    render.add_argument("--threads", type=int, default=0, help="0 = all cores")
    render.add_argument("--time-limit", type=float, default=0.0, help="seconds; stops after the pass that passes it")
    render.add_argument("--resolution", type=int, nargs=2, metavar=("W", "H"), help="override the render settings")
    render.add_argument("--camera", help="camera prim path (default: the render settings' camera)")
    render.add_argument("--filter", default="box", choices=["box", "gaussian"], help="pixel reconstruction filter")
    render.add_argument("--png", help="PNG path (default: next to the EXR)")
    render.add_argument("--no-png", action="store_true")
    render.add_argument("--display", default="", help="OCIO display (default: the config's)")
    render.add_argument("--view", default="", help="OCIO view (default: the config's)")
    render.add_argument("--exposure", type=float, default=0.0, help="stops, applied before the view transform")
    owners = add_integrator_flags(render)
    inspect = sub.add_parser("inspect", help="list what a scene contains and needs")
    inspect.add_argument("scene")
    return parser, owners


def main(argv=None):
    parser, owners = build_parser()
    args = parser.parse_args(argv)
    try:
        if args.command == "render":
            return cmd_render(args, owners)
        if args.command == "inspect":
            return cmd_inspect(args)
    except SceneError as error:
        print(f"gi: error: {error}", file=sys.stderr)
        return 2
    except (ValueError, RuntimeError) as error:
        print(f"gi: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("gi: interrupted", file=sys.stderr)
        return 130
    return 1
