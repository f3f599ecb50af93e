"""`gi study --thesis caixa|sibenik`: the thesis's RMSE tables beside ours.

The thesis (chapter 4) rendered each scene at 1024x768 with 4 samples per pixel, every technique at
the parameters of its tables (4.1-4.3 for Caixa, our Cornell box; 4.9-4.11 for the Catedral de Sao
Jaco, our Sibenik), and scored each image by its RMSE (eq. 3.1) against a path-traced reference:
tables 4.4 and 4.12. Its images were 8-bit, and its figures (4.9 to 68.6) are on that 0-255 scale,
which is our study's "RMSE sRGB8" (gi.metrics.rmse_srgb8). The parameters are the presets `thesis`
and `thesis-sibenik` (gi._core.presets()); each run is given its preset's values explicitly, so
that results.csv records what the renderer was told.

The study is gi.study's, on a reference this module renders once with gi.reference (the path tracer
at its defaults: unbounded depth) and keeps in the output folder as reference.exr; a later run with
the same scene and size reuses it. The thesis reports no times; we add ours, with preprocessing and
peak memory.
"""
from __future__ import annotations

import csv
import sys
from dataclasses import dataclass
from pathlib import Path

from .errors import warn

THESIS_RESOLUTION = (1024, 768)
THESIS_SPP = 4
REFERENCE_FILE = "reference.exr"
TABLE_FILE = "thesis.csv"
# The reference stops on time: its stopping rule (the image mean's standard error) is met within
# seconds, long before single pixels are quiet enough to score 4-spp images against.
DEFAULT_REFERENCE_SECONDS = 1800.0
REFERENCE_TARGET_ERROR = 1e-9

# The thesis's rows in its order: (its name for the technique, our integrator).
TECHNIQUES = [("irradiance caching", "irradianceCache"),
              ("adaptive irradiance caching", "adaptiveIrradianceCache"),
              ("path tracing", "path"),
              ("photon mapping with irradiance cache", "photonMapIrradianceCache"),
              ("photon mapping with final gathering", "photonMapFinalGather")]


@dataclass(frozen=True)
class ThesisScene:
    key: str
    thesis_name: str
    scene: str              # relative to the repository's root
    preset: str             # gi._core.presets() name holding the parameter tables
    parameter_tables: str
    rmse_table: str
    rmse: tuple             # the RMSE table's values, in TECHNIQUES' order


SCENES = {
    "caixa": ThesisScene("caixa", "Caixa", "scenes/cornell/cornell.usda", "thesis", "4.1-4.3", "4.4",
                         (10.5463, 9.26403, 7.69168, 7.88408, 4.89016)),
    "sibenik": ThesisScene("sibenik", "Catedral de São Jacó", "scenes/sibenik/sibenik.usda", "thesis-sibenik",
                           "4.9-4.11", "4.12", (15.4329, 28.4363, 42.4436, 64.3173, 68.5992)),
}

# (header, row key, format) of the side-by-side table; the thesis's column comes first.
TABLE_COLUMNS = [("our RMSE sRGB8", "rmse_srgb8", ".2f"), ("our FLIP", "flip", ".4f"),
                 ("seconds", "seconds", ".2f"), ("preprocessing s", "preprocess_seconds", ".2f"),
                 ("peak MB", "peak_memory_mb", ".0f")]


def typed_params(values, declared):
    """A preset's values (numbers) as the integrator declares them: 5, not 5.0; True, not 1.0."""
    kinds = {param["name"]: param["type"] for param in declared}
    cast = {"int": lambda x: int(round(x)), "bool": bool, "float": float}
    return {name: cast[kinds[name]](value) for name, value in values.items()}


def thesis_runs(thesis, presets, catalog, spp, integrators=None):
    """gi.study RunSpecs of the thesis's five techniques with their preset's parameters (only
    `integrators` when given)."""
    from .study import RunSpec
    by_name = {preset["name"]: preset for preset in presets}
    if thesis.preset not in by_name:
        raise ValueError(f"the renderer has no preset '{thesis.preset}' (have: {', '.join(by_name)})")
    params = by_name[thesis.preset]["params"]
    declared = {info["name"]: info["params"] for info in catalog}
    chosen = [(label, name) for label, name in TECHNIQUES if not integrators or name in integrators]
    unknown = sorted(set(integrators or []) - {name for _, name in TECHNIQUES})
    if unknown or not chosen:
        raise ValueError(f"--integrators {', '.join(integrators)}: the thesis's techniques are "
                         f"{', '.join(name for _, name in TECHNIQUES)}")
    return [RunSpec(label, name, typed_params(params.get(name, {}), declared[name]), spp) for label, name in chosen]


def cached_reference(path, scene, resolution):
    """True when `path` is a gi reference of `scene` at `resolution` (then it is reused)."""
    from .study import load_reference
    if not path.exists():
        return False
    pixels, meta = load_reference(path)
    size = (pixels.shape[1], pixels.shape[0])
    same_scene = Path(meta.get("gi:scene", "")).resolve() == Path(scene).resolve()
    if meta.get("gi:reference") == "1" and same_scene and size == tuple(resolution):
        return True
    warn(f"{path}: made for {meta.get('gi:scene', '?')} at {size[0]}x{size[1]}, not {scene} at "
         f"{resolution[0]}x{resolution[1]}; rendering a new reference over it")
    return False


def ensure_reference(scene, output, resolution, max_seconds, seed, threads, log=print):
    """The path of the study's reference: output/reference.exr, rendered unless a matching one is there."""
    from .reference import make_reference, summary
    path = Path(output) / REFERENCE_FILE
    if cached_reference(path, scene, resolution):
        log(f"reusing the reference {path}")
        return path
    log(f"rendering the reference {path} ({resolution[0]}x{resolution[1]}, path tracing at unbounded depth, "
        f"{max_seconds:g} s)")
    reference = make_reference(scene, path, max_seconds, REFERENCE_TARGET_ERROR, resolution, seed, threads,
                               show_progress=sys.stderr.isatty())
    log(summary(reference, REFERENCE_TARGET_ERROR))
    return path


def side_by_side(thesis, rows):
    """(title, headers, cells) of the thesis's RMSE table beside ours, and the CSV's records."""
    from .report import number
    thesis_rmse = dict(zip((label for label, _ in TECHNIQUES), thesis.rmse))
    spp = {row["spp"] for row in rows}
    title = (f"Thesis table {thesis.rmse_table} ({thesis.thesis_name}) beside ours: preset {thesis.preset} "
             f"(tables {thesis.parameter_tables}), {'/'.join(map(str, sorted(spp)))} spp; "
             f"the thesis reports no times")
    headers = ["technique", f"thesis RMSE (table {thesis.rmse_table})"] + [h for h, _, _ in TABLE_COLUMNS]
    cells, records = [], []
    for row in (row for row in rows if row["label"] in thesis_rmse):  # not the denoised rows
        cells.append([row["label"], number(thesis_rmse[row["label"]], "g")]  # as the thesis prints them
                     + [number(row[key], spec) for _, key, spec in TABLE_COLUMNS])
        records.append({"technique": row["label"], "integrator": row["integrator"],
                        "thesis_rmse": thesis_rmse[row["label"]],
                        **{key: row[key] for _, key, _ in TABLE_COLUMNS},
                        "spp": row["spp"], "params": row["params"]})
    return (title, headers, cells), records


def write_table(path, records):
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(records[0]))
        writer.writeheader()
        writer.writerows(records)


def run_thesis_study(key, output, scene=None, resolution=None, spp=THESIS_SPP, reference=None,
                     reference_seconds=DEFAULT_REFERENCE_SECONDS, integrators=None, seed=0, threads=0,
                     denoise=None, log=print):
    """The thesis's study of scene `key` into `output`; returns (StudyResult, the table's records).
    denoise: --denoise's text (default: no denoised rows, the thesis has none)."""
    from .render import require_core
    from .study import check_runs, denoise_choice, run_study
    thesis = SCENES[key]
    scene = Path(scene or thesis.scene)
    if not scene.exists():
        raise ValueError(f"{scene}: no such scene (run from the repository's root, or give the scene; Sibenik "
                         f"needs `bash scripts/import-scenes.sh` once)")
    resolution = tuple(resolution or THESIS_RESOLUTION)
    core = require_core()
    runs = thesis_runs(thesis, core.presets(), core.integrators(), spp, integrators)
    check_runs(runs, core.integrators())
    reference = reference or ensure_reference(scene, output, resolution, reference_seconds, seed, threads, log)
    study = run_study(scene, reference, runs, output, resolution, seed, threads, show_progress=sys.stderr.isatty(),
                      log=log, denoise=denoise_choice(denoise, runs) or [],
                      lead_tables=lambda rows: [side_by_side(thesis, rows)[0]])
    records = side_by_side(thesis, study.rows[1:])[1]
    write_table(Path(output) / TABLE_FILE, records)
    return study, records


def cmd_thesis_study(args):
    if args.budgets or args.params_file or args.camera:
        raise ValueError("--thesis sets the runs and the camera (the scene's); drop --budgets, --params-file, --camera")
    study, _ = run_thesis_study(args.thesis, args.output, args.scene, args.resolution, args.spp or THESIS_SPP,
                                args.reference, args.reference_seconds or DEFAULT_REFERENCE_SECONDS,
                                args.integrators, args.seed, args.threads, args.denoise)
    print(f"thesis table -> {study.output}/{TABLE_FILE}, {study.output}/report.md")
    return 0
