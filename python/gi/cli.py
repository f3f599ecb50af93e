"""The `gi` command: `gi render` (a USD scene to a linear EXR and a display PNG), `gi inspect`, and
`gi reference` / `gi study` (error against run time, in gi.reference and gi.study).

gi._core is imported lazily, so `gi --help` and `gi inspect` work before the renderer is built."""
import argparse
import re
import sys

from . import __version__
from .errors import DenoiserMissing, SceneError
from .render import COMPLEXITY_REFINE_LEVELS, DEFAULT_COMPLEXITY, CoreMissing, integrator_catalog, preset_catalog

PARAM_TYPES = {"int": int, "float": float}


def kebab(name):
    """pathDepth -> path-depth"""
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "-", name).lower()


# -- integrator parameters as flags --------------------------------------------------------------

class IntegratorFlags:
    """Command-line flags generated from every integrator's parameter list."""

    def __init__(self, catalog):
        self.params = {}    # camelCase name -> its description (the first integrator declaring it wins)
        self.owners = {}    # integrator name -> names of the parameters it takes
        self.defaults = {}  # camelCase name -> {integrator: its own default}
        for integrator in catalog:
            self.owners[integrator["name"]] = {p["name"] for p in integrator["params"]}
            for param in integrator["params"]:
                self.params.setdefault(param["name"], param)
                self.defaults.setdefault(param["name"], {})[integrator["name"]] = param["default"]

    def default_text(self, name):
        """'default 5' when every integrator that takes it agrees, else each one's own default."""
        values = self.defaults[name]
        if len(set(map(str, values.values()))) == 1:
            return f"default {next(iter(values.values()))}; {', '.join(sorted(values))}"
        return "defaults: " + ", ".join(f"{integrator} {value}" for integrator, value in sorted(values.items()))

    def users(self, name):
        return sorted(i for i, names in self.owners.items() if name in names)

    def add_to(self, parser):
        group = parser.add_argument_group(
            "integrator parameters", "generated from gi._core.integrators(); each integrator takes its own")
        for name, param in sorted(self.params.items()):
            # default=None tells "not given" apart, so the integrator's own default applies.
            options = dict(dest=f"param_{name}", default=None,
                           help=f"{param['description']} ({param['min']}..{param['max']}; "
                                f"{self.default_text(name)})")
            if param["type"] == "bool":
                options["action"] = argparse.BooleanOptionalAction
            else:
                options.update(type=PARAM_TYPES[param["type"]], metavar=param["type"].upper())
            group.add_argument(f"--{kebab(name)}", **options)

    def chosen(self, args, parser):
        """{name: value} of the given flags; a flag the chosen integrator does not take is an error
        (a typo or a flag meant for another integrator must not render something else silently)."""
        given = {key[len("param_"):]: value for key, value in vars(args).items()
                 if key.startswith("param_") and value is not None}
        takes = self.owners.get(args.integrator, set())
        foreign = sorted(set(given) - takes)
        if foreign:
            parser.error(", ".join(f"--{kebab(name)}" for name in foreign) +
                         f" {'is not a parameter' if len(foreign) == 1 else 'are not parameters'} of "
                         f"'{args.integrator}' (it takes: {', '.join('--' + kebab(n) for n in sorted(takes))})")
        chosen = dict(given)
        for name, value in chosen.items():
            low, high = self.params[name]["min"], self.params[name]["max"]
            if not low <= value <= high:
                parser.error(f"--{kebab(name)} {value} is outside {low}..{high}")
        return chosen


def cmd_inspect(args):
    from .inspect import format_report, inspect_scene
    print(format_report(inspect_scene(args.scene)))
    return 0


# -- the parser ----------------------------------------------------------------------------------

def positive_int(text):
    value = int(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"{text} is not a positive integer")
    return value


def add_render_parser(commands, flags):
    render = commands.add_parser("render", help="render a USD scene to a linear EXR and a display PNG")
    render.add_argument("scene", help="a USD file (.usd, .usda, .usdc, .usdz)")
    render.add_argument("-o", "--output",
                        help="EXR path (default: every RenderProduct of the render settings, each with its "
                             "productName and RenderVars; without any, out/<scene name>.exr)")
    render.add_argument("--integrator", choices=sorted(flags.owners) or None,
                        help="light transport technique (default: the render settings' gi:integrator, else path)")
    presets = preset_catalog()
    render.add_argument("--preset", choices=[p["name"] for p in presets] or None,
                        help="a named parameter set under the flags given: " +
                             "; ".join(f"{p['name']}: {p['description']}" for p in presets) +
                             " (default: the render settings' gi:preset, else none: the integrator's defaults, "
                             "unbounded depths)")
    render.add_argument("--spp", type=positive_int,
                        help="camera samples per pixel (default: the render settings' gi:samples, else 16)")
    render.add_argument("--seed", type=int,
                        help="sampler seed (default: the render settings' gi:seed, else 0); renders are deterministic")
    render.add_argument("--threads", type=int, default=0, help="worker threads (default 0 = all cores)")
    render.add_argument("--time-limit", type=float, metavar="S",
                        help="end the render, preprocessing included, within S seconds (default: the render "
                             "settings' gi:timeLimit, else 0 = none; with --integrator auto, the budget the "
                             "technique is chosen for)")
    render.add_argument("--resolution", type=positive_int, nargs=2, metavar=("W", "H"),
                        help="image size (default: the stage's render settings, else 512 512)")
    render.add_argument("--camera", metavar="PRIM", help="camera prim path (default: the render settings' camera)")
    render.add_argument("--allow-missing", action="store_true",
                        help="render a stage whose sublayers, references or payloads cannot all be found "
                             "(default: an error naming them)")
    render.add_argument("--complexity", default=DEFAULT_COMPLEXITY, choices=list(COMPLEXITY_REFINE_LEVELS),
                        help="subdivision meshes refined 0, 1, 2 or 3 times with OpenSubdiv, as usdrecord's "
                             f"--complexity (default {DEFAULT_COMPLEXITY}, as usdrecord's: the control cage)")
    render.add_argument("--purposes", metavar="PURPOSE[,PURPOSE...]", type=purpose_list,
                        help="purposes rendered besides default, as usdrecord's --purposes (default: the render "
                             "settings' includedPurposes, else render; usdrecord's default is proxy)")
    render.add_argument("--settings", metavar="PRIM",
                        help="the RenderSettings prim whose RenderProducts are written when -o is not given "
                             "(default: the stage's renderSettingsPrimPath, else the first)")
    render.add_argument("--filter", default="box", choices=["box", "gaussian"], help="pixel filter (default box)")
    render.add_argument("--frames", type=frame_range, metavar="RANGE",
                        help="render these frames (time codes) in one process: 1-48, 1-48:2, 1,5,10-20; "
                             "frame F is rendered with seed + F; -o then names each frame with #### or $F4 "
                             "(default: one image at the earliest time, as usdrecord renders)")
    render.add_argument("--tile", type=tile_spec, metavar="CxR:I",
                        help="render only tile I (0-based, row by row from the top left) of the image cut into "
                             "C columns and R rows; its pixels equal the whole image's bit for bit "
                             "(`gi merge-tiles` joins the tiles; used by `gi job --tiles`)")
    render.add_argument("--png", help="PNG path (default: the EXR's path with .png)")
    render.add_argument("--no-png", action="store_true", help="write only the EXR")
    render.add_argument("--display", default="", help="OCIO display for the PNG (default: the config's)")
    render.add_argument("--view", default="", help="OCIO view for the PNG (default: the config's)")
    render.add_argument("--exposure", type=float, default=0.0,
                        help="stops applied before the PNG's view transform")
    render.add_argument("--denoise", action="store_true",
                        help="denoise the colour with Intel Open Image Denoise 2.x, guided by the albedo and "
                             "normal AOVs (needs `pip install pyoidn`, or $GI_OIDN_LIBRARY); the EXR keeps "
                             "the raw colour as noisy.R/G/B, the PNG shows the denoised one")
    flags.add_to(render)
    return render


def add_common_render_options(parser, size_and_camera_from="the stage's render settings"):
    """--resolution, --seed, --threads, --camera, as `gi render` has them."""
    parser.add_argument("--resolution", type=positive_int, nargs=2, metavar=("W", "H"),
                        help=f"image size (default: {size_and_camera_from})")
    parser.add_argument("--seed", type=int, default=0, help="sampler seed (default 0)")
    parser.add_argument("--threads", type=int, default=0, help="worker threads (default 0 = all cores)")
    parser.add_argument("--camera", metavar="PRIM", help=f"camera prim path (default: {size_and_camera_from})")


def add_reference_parser(commands):
    reference = commands.add_parser(
        "reference", help="render an unbiased path-traced reference EXR progressively",
        description="Renders batches of the path tracer until the relative standard error of the image "
                    "mean is under --target-error or --max-seconds pass; writes spp, time and the error "
                    "estimate into the EXR's metadata.")
    reference.add_argument("scene", help="a USD file")
    reference.add_argument("-o", "--output", required=True, help="EXR path")
    reference.add_argument("--max-seconds", type=float, default=3600.0, metavar="S",
                           help="time limit (default 3600; 0 = none)")
    reference.add_argument("--target-error", type=float, default=0.002, metavar="E",
                           help="relative standard error of the image mean to reach (default 0.002)")
    reference.add_argument("--sun-by-photons", action="store_true",
                           help="where a sun is seen only through glass: the path tracer renders every light "
                                "but the distant lights (half of --max-seconds), the progressive photon map the "
                                "distant lights alone for as long, and the reference is their sum (the path "
                                "tracer finds a sun behind glass too rarely to converge)")
    add_common_render_options(reference)


def positive_float(text):
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"{text} is not a positive number")
    return value


def frame_range(text):
    from .frames import parse_frames
    try:
        return parse_frames(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def tile_spec(text):
    from .tiles import parse_tile
    try:
        return parse_tile(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def tiling_spec(text):
    from .tiles import parse_tile
    try:
        return parse_tile(text, with_index=False)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def purpose_list(text):
    """usdrecord's --purposes: names separated by commas and/or spaces."""
    return text.replace(",", " ").split()


def comma_list(text):
    return [item.strip() for item in text.split(",") if item.strip()]


def seconds_list(text):
    try:
        values = [float(item) for item in comma_list(text)]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of seconds") from None
    if not values or min(values) <= 0:
        raise argparse.ArgumentTypeError(f"{text!r}: budgets must be positive seconds")
    return values


def add_study_parser(commands, flags):
    study = commands.add_parser(
        "study", help="compare integrators against a reference at equal time or fixed parameters",
        description="Renders every integrator at each time budget (or each run of a parameter table) and "
                    "writes results.csv, error_vs_time.png, the renders, difference images and "
                    "report.md / report.html into the output folder.")
    study.add_argument("scene", nargs="?", help="a USD file (with --thesis: default the thesis scene's)")
    study.add_argument("--reference", help="reference EXR (e.g. from `gi reference`; required without --thesis)")
    study.add_argument("--integrators", type=comma_list,
                       help=f"comma-separated (default: all: {', '.join(sorted(flags.owners)) or 'none built'})")
    runs = study.add_mutually_exclusive_group()
    runs.add_argument("--budgets", type=seconds_list, help="comma-separated seconds per run (default 1,2,4)")
    runs.add_argument("--params-file", help="JSON table of runs at fixed parameters (see gi.study)")
    study.add_argument("-o", "--output", default="study", metavar="DIR", help="output folder (default ./study)")
    study.add_argument("--denoise", metavar="LIST",
                       help="comma-separated integrators whose runs also get a '+ denoise' row (Open Image "
                            "Denoise), or 'none' (default: path and photonMapFinalGather when the study has them; "
                            "skipped with a warning without pyoidn)")
    add_common_render_options(study, "the reference's")
    add_thesis_options(study)


def add_thesis_options(study):
    from .thesis import DEFAULT_REFERENCE_SECONDS, SCENES, THESIS_RESOLUTION, THESIS_SPP
    thesis = study.add_argument_group(
        "the thesis's tables", "--thesis SCENE renders the thesis's five techniques at its resolution, samples and "
        f"parameters ({THESIS_RESOLUTION[0]}x{THESIS_RESOLUTION[1]} unless --resolution; preset thesis / "
        "thesis-sibenik) against a path-traced reference it renders into the output "
        "folder (reference.exr, reused by later runs), and writes thesis.csv and the table beside the thesis's "
        "RMSE (tables 4.4, 4.12) into report.md; no denoised rows unless --denoise")
    thesis.add_argument("--thesis", choices=sorted(SCENES),
                        help="; ".join(f"{key}: {s.thesis_name}, {s.scene}, preset {s.preset}, table {s.rmse_table}"
                                       for key, s in SCENES.items()))
    thesis.add_argument("--spp", type=positive_int,
                        help=f"camera samples per pixel of every run (default {THESIS_SPP}, the thesis's)")
    thesis.add_argument("--reference-seconds", type=positive_float, metavar="S",
                        help=f"time for the reference when there is none to reuse (default {DEFAULT_REFERENCE_SECONDS:g})")


def add_import_parser(commands):
    imp = commands.add_parser(
        "import", help="convert an OBJ or glTF file to USD (meshes, UsdPreviewSurface materials, textures)",
        description="Converts a Wavefront OBJ/MTL or glTF 2.0 file into a USD layer. Textures are referenced "
                    "where they are (relative to the output), never copied. SOURCE may be a path or a path "
                    "inside the asset folder (--assets, $GI_ASSETS, default ../shared/assets).")
    imp.add_argument("source", help="an .obj, .gltf or .glb file")
    imp.add_argument("-o", "--output", required=True, help="USD file to write (.usdc, .usda or .usd)")
    imp.add_argument("--assets", metavar="DIR", help="asset folder (default: $GI_ASSETS, else ../shared/assets)")
    imp.add_argument("--up-axis", choices=["Y", "Z"], default="Y", help="the source's up axis (default Y)")
    imp.add_argument("--meters-per-unit", type=float, default=1.0, help="the source's unit in metres (default 1)")
    imp.add_argument("--absolute-paths", action="store_true",
                     help="write absolute texture paths (default: relative to the output file)")
    imp.add_argument("--name", help="name of the root prim (default: the source's file name)")


def add_merge_tiles_parser(commands):
    merge = commands.add_parser(
        "merge-tiles", help="join the tile EXRs of `gi render --tile` into whole frames",
        description="Reads each frame's tiles (EXRs whose data windows cover the image once) and writes the whole "
                    "image with the same channels: the pixels of `gi render` without --tile, bit for bit.")
    merge.add_argument("tiles_pattern", metavar="TILES",
                       help="tile EXR paths with {tile} for the tile index and #### or $F4 for the frame")
    merge.add_argument("--tiles", type=tiling_spec, required=True, metavar="CxR", help="the tiling, e.g. 2x2")
    merge.add_argument("--frames", type=frame_range, default=[0], metavar="RANGE",
                       help="the frames to merge (default: 0, for paths without a frame token)")
    merge.add_argument("-o", "--output", required=True, help="merged EXR path, with #### or $F4 for the frame")
    merge.add_argument("--no-png", action="store_true", help="write only the EXR")


def add_job_parser(commands):
    job = commands.add_parser(
        "job", help="write an Open Job Description job bundle that renders frames on a farm",
        usage="gi job SCENE --frames RANGE -o DIR [--chunk N] [--tiles CxR] [--name NAME] [-- RENDER OPTIONS]",
        description="Writes DIR/template.yaml and DIR/parameter_values.yaml: an OpenJD job (Deadline Cloud's job "
                    "bundle) whose tasks run `gi render` on chunks of frames, or with --tiles on tiles of each "
                    "frame and then `gi merge-tiles`. Options after -- go to every `gi render` (--spp, "
                    "--integrator, --seed, --resolution, ...).",
        epilog="example: gi job shot.usda --frames 1-240 --chunk 8 --tiles 2x2 -o job -- --spp 256")
    job.add_argument("scene", help="a USD file")
    job.add_argument("--frames", type=frame_range, required=True, metavar="RANGE", help="frames: 1-240, 1-48:2, ...")
    job.add_argument("--chunk", type=positive_int, default=1, metavar="N", help="frames per task (default 1; at most 150)")
    job.add_argument("--tiles", type=tiling_spec, metavar="CxR",
                     help="render each frame as C x R tiles, one task each, then merge them (bit for bit the "
                          "whole frame; each tile repeats the integrator's preprocessing)")
    job.add_argument("-o", "--output", required=True, metavar="DIR", help="the job bundle's folder")
    job.add_argument("--name", help="the job's name (default: gi <scene name>)")
    job.set_defaults(render_args=[])  # what follows `--` (main() splits it off): gi render options for every task


def build_parser():
    """(parser, its render subparser, the integrator flags)."""
    parser = argparse.ArgumentParser(prog="gi", description="hdGi: CPU global illumination for USD scenes")
    parser.add_argument("--version", action="version", version=f"gi {__version__}")
    commands = parser.add_subparsers(dest="command", required=True)
    flags = IntegratorFlags(integrator_catalog())
    render = add_render_parser(commands, flags)
    inspect = commands.add_parser("inspect", help="list what a scene contains (counts, lights, textures)")
    inspect.add_argument("scene", help="a USD file")
    add_reference_parser(commands)
    add_study_parser(commands, flags)
    add_import_parser(commands)
    add_merge_tiles_parser(commands)
    add_job_parser(commands)
    return parser, render, flags


def main(argv=None):
    parser, render_parser, flags = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    passed_on = []  # `gi job ... -- RENDER OPTIONS`: options for the job's `gi render` tasks
    if argv[:1] == ["job"] and "--" in argv:
        argv, passed_on = argv[:argv.index("--")], argv[argv.index("--") + 1:]
    args = parser.parse_args(argv)
    if args.command == "job":
        args.render_args = passed_on
    try:
        if args.command == "render":
            from .render_command import cmd_render
            return cmd_render(args, flags, render_parser)
        if args.command == "reference":
            from .reference import cmd_reference
            return cmd_reference(args)
        if args.command == "study":
            from .study import cmd_study
            return cmd_study(args)
        if args.command == "job":
            from .job import cmd_job
            return cmd_job(args, render_parser, flags)
        if args.command == "merge-tiles":
            from .tiles import cmd_merge_tiles
            return cmd_merge_tiles(args)
        if args.command == "import":
            from .importer import cmd_import
            return cmd_import(args)
        return cmd_inspect(args)
    except (SceneError, CoreMissing, DenoiserMissing, ValueError) as error:  # ValueError: the renderer rejects a setting
        print(f"gi: error: {error}", file=sys.stderr)
        return 2
    except (RuntimeError, OSError) as error:  # e.g. an output file that cannot be written
        print(f"gi: error: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("gi: interrupted", file=sys.stderr)
        return 130
