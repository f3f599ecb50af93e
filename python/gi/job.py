"""`gi job`: a farm job bundle for an Open Job Description engine (AWS Deadline Cloud, or
`openjd run` locally): template.yaml and parameter_values.yaml, as Deadline Cloud's job bundles
have them.

The template's steps run `gi render` on chunks of frames (OpenJD's TASK_CHUNKING extension:
one task per chunk, each a range expression `gi render --frames` takes), or with --tiles on every
tile of every chunk and then `gi merge-tiles` on each chunk. The render options after `--` are
checked here by `gi render`'s own parser and passed to every task unchanged, so a task renders what
the same `gi render --frames` would: the same seeds per frame, the merged tiles equal to the whole
frames bit for bit."""
import json
import shlex
from pathlib import Path

from .frames import format_frames
from .tiles import why_tiles_differ

TEMPLATE = "template.yaml"
PARAMETER_VALUES = "parameter_values.yaml"
# The flags a job sets itself in every task.
OWN_FLAGS = ("-o", "--output", "--frames", "--tile", "--png")
MAX_CHUNK = 150  # TASK_CHUNKING's largest defaultTaskCount


def job_parameters(scene, output_dir, frames, chunk):
    """The job's parameters: definitions (with defaults) and the values of this job."""
    definitions = [
        {"name": "SceneFile", "type": "PATH", "objectType": "FILE", "dataFlow": "IN",
         "description": "the USD stage to render"},
        {"name": "OutputDir", "type": "PATH", "objectType": "DIRECTORY", "dataFlow": "OUT",
         "description": "where the frames go"},
        {"name": "Frames", "type": "STRING", "default": format_frames(frames),
         "description": "frames to render: an OpenJD range expression (1-240, 1-48:2, 1,5,10-20)"},
        {"name": "ChunkSize", "type": "INT", "default": chunk, "minValue": 1, "maxValue": MAX_CHUNK,
         "description": "frames per task"},
        {"name": "Gi", "type": "STRING", "default": "gi",
         "description": "the gi command on the workers (a name on their PATH, or a path)"},
    ]
    values = {"SceneFile": str(Path(scene).resolve()), "OutputDir": str(Path(output_dir).resolve() / "frames")}
    return definitions, values


def frame_chunks():
    return {"name": "Frame", "type": "CHUNK[INT]", "range": "{{Param.Frames}}",
            "chunks": {"defaultTaskCount": "{{Param.ChunkSize}}", "rangeConstraint": "NONCONTIGUOUS"}}


def run_action(arguments):
    return {"actions": {"onRun": {"command": "{{Param.Gi}}", "args": arguments}}}


def template(scene, render_args, tiling, name, frames, chunk):
    """The job template (a dict in the jobtemplate-2023-09 schema); `frames` and `chunk` are the
    defaults of its Frames and ChunkSize parameters."""
    stem = Path(scene).stem
    frames_out = "{{Param.OutputDir}}/" + stem + ".####.exr"
    render = ["render", "{{Param.SceneFile}}", "--frames", "{{Task.Param.Frame}}", *render_args]
    definitions, _ = job_parameters(scene, ".", frames, chunk)
    job = {"specificationVersion": "jobtemplate-2023-09", "extensions": ["TASK_CHUNKING"], "name": name,
           "parameterDefinitions": definitions}
    if tiling is None:
        job["steps"] = [{"name": "Render", "parameterSpace": {"taskParameterDefinitions": [frame_chunks()]},
                         "script": run_action(render + ["-o", frames_out])}]
        return job
    tiles_out = "{{Param.OutputDir}}/tiles/" + stem + ".####.tile{{Task.Param.Tile}}.exr"
    job["steps"] = [
        {"name": "RenderTiles",
         "parameterSpace": {"taskParameterDefinitions": [
             frame_chunks(), {"name": "Tile", "type": "INT", "range": f"0-{tiling.count - 1}"}]},
         "script": run_action(render + ["--tile", f"{tiling.columns}x{tiling.rows}:{{{{Task.Param.Tile}}}}",
                                        "-o", tiles_out])},
        {"name": "MergeTiles", "dependencies": [{"dependsOn": "RenderTiles"}],
         "parameterSpace": {"taskParameterDefinitions": [frame_chunks()]},
         "script": run_action(["merge-tiles", "{{Param.OutputDir}}/tiles/" + stem + ".####.tile{tile}.exr",
                               "--tiles", f"{tiling.columns}x{tiling.rows}", "--frames", "{{Task.Param.Frame}}",
                               "-o", frames_out])},
    ]
    return job


def to_yaml(data):
    """YAML through JSON's syntax (YAML 1.2 is a superset of JSON): no YAML library needed, and
    every string quoted, so a format string like {{Param.Frames}} is never read as a mapping."""
    return json.dumps(data, indent=2) + "\n"


def check_render_args(render_args, render_parser, scene):
    """`gi render`'s parser on the options the tasks get: a typo fails here, not on the farm."""
    for flag in OWN_FLAGS:
        if flag in render_args or any(a.startswith(flag + "=") for a in render_args):
            raise ValueError(f"{flag} is set by the job itself; leave it out of the render options")
    return render_parser.parse_args([str(scene), *render_args])


def cmd_job(args, render_parser, flags):
    scene = Path(args.scene)
    if args.chunk > MAX_CHUNK:
        raise ValueError(f"--chunk {args.chunk}: an OpenJD task chunk holds at most {MAX_CHUNK} frames")
    if not scene.exists():
        raise ValueError(f"{scene}: no such file")
    render_args = list(args.render_args)
    try:
        render = check_render_args(render_args, render_parser, scene)
    except SystemExit:  # argparse has printed what is wrong with them
        raise ValueError(f"the render options {shlex.join(render_args)!r} are not valid for gi render") from None
    flags.chosen(render, render_parser)  # integrator flags the integrator does not take
    if args.tiles is not None and why_tiles_differ(render):
        raise ValueError(f"--tiles with {why_tiles_differ(render)}")
    if render.integrator == "auto" and len(args.frames) > args.chunk:
        # One gi render keeps its first frame's choice for the rest; separate tasks cannot.
        raise ValueError(f"--integrator auto with {-(-len(args.frames) // args.chunk)} chunks: each task would "
                         "choose its own technique from timed pilots, and the sequence could switch techniques "
                         "between chunks; give the technique auto chooses (gi render --integrator auto says), "
                         "or one chunk")
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    name = args.name or f"gi {scene.stem}"
    job = template(scene, render_args, args.tiles, name, args.frames, args.chunk)
    _, values = job_parameters(scene, out, args.frames, args.chunk)
    values.update(Frames=format_frames(args.frames), ChunkSize=args.chunk)
    (out / TEMPLATE).write_text(to_yaml(job))
    (out / PARAMETER_VALUES).write_text(to_yaml(
        {"parameterValues": [{"name": k, "value": v} for k, v in values.items()]}))
    steps = ", ".join(step["name"] for step in job["steps"])
    chunks = -(-len(args.frames) // args.chunk)
    tasks = chunks * (args.tiles.count + 1 if args.tiles else 1)
    print(f"{out / TEMPLATE}: {len(args.frames)} frames in {chunks} chunks of {args.chunk}"
          f"{f', {args.tiles.count} tiles each' if args.tiles else ''}; steps {steps}; {tasks} tasks")
    print(f"run it here:   openjd run {out / TEMPLATE} -p {shlex.quote(json.dumps(values))} "
          f"--step {job['steps'][-1]['name']}{' --run-dependencies' if args.tiles else ''}")
    print(f"or on Deadline Cloud:   deadline bundle submit {out}")
    return 0
