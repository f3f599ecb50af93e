"""`gi study`: every integrator against a reference, at equal time or at fixed parameters.

Two kinds of study (thesis 3.4 and chapter 4):
- equal time: each integrator renders with RenderSettings.time_limit = each budget; the renderer keeps
  it, preprocessing included, to within a few pixels' samples (preprocessing that would take more than
  half of it scales itself down and says so in a warning and the preprocess_scaled_down statistic;
  the last pass stops at the deadline, leaving some pixels with one pass fewer), and the tables show
  the measured seconds beside the budget;
- a parameter table (--params-file), to reproduce the thesis's tables 4.1-4.15:

    {"spp": 4,                                   # default for every run (the thesis used 4)
     "runs": [{"label": "IC, a = 0.2",           # optional, must be unique
               "integrator": "irradianceCache",
               "params": {"accuracy": 0.2},      # checked against _core.integrators()
               "spp": 4,                         # optional
               "time_limit": 0}]}                # optional, seconds

  A bare list of runs is accepted too.

Runs share one loaded scene (loading is not what is compared) and happen in this process, one after
another; each run's peak memory is its own because the kernel's high-water mark is reset before it.
Outputs go into one folder; gi.report writes the plot and the reports from the rows.

Denoised rows: each run of a technique in --denoise (default DEFAULT_DENOISED, the techniques whose
FLIP Open Image Denoise lowers) is denoised too and adds a row "<technique> + denoise" with the same
render and its time plus the denoising's (denoise_seconds), so that error against time shows what a
user of a denoised renderer gets. Without Open Image Denoise the default skips them with a warning;
an explicit --denoise list is then an error.
"""
from __future__ import annotations

import csv
import json
import re
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import metrics
from .errors import DenoiserMissing

DEFAULT_BUDGETS = [1.0, 2.0, 4.0]
DEFAULT_TABLE_SPP = 4          # the thesis's samples per pixel
BUDGET_SPP_CAP = 1 << 24       # equal-time runs stop on time; spp only has to be out of reach
CHECK_LABEL = "reference"      # the reference against itself: every error must be 0
# Techniques whose runs get a denoised row by default: those whose FLIP Open Image Denoise lowered by
# more than a few percent (Cornell box, 128x128, 4 spp, against 4096 spp; README, "Denoising"): path
# 0.088 -> 0.060, photonMapFinalGather 0.034 -> 0.029. The caches' and photon maps' smooth error is
# bias, not noise: irradiance caching, its adaptive form, photonMapIrradianceCache and
# progressivePhotonMap gained 1-2%, direct lighting nothing.
DEFAULT_DENOISED = ["path", "photonMapFinalGather"]
DENOISED_SUFFIX = " + denoise"

# result.stats keys every render has (documented in _core.pyi); the others are the integrator's own.
COMMON_STATS = {"seconds", "preprocess_seconds", "render_seconds", "rays", "rays_per_second", "camera_samples",
                "samples_per_second", "non_finite_samples", "clamped_samples", "depth_capped_paths",
                "peak_memory_bytes", "spp", "partial_pass_pixels", "partial_pass_samples", "preprocess_scaled_down"}

RUN_COLUMNS = ["label", "integrator", "budget_seconds", "spp", "params", "seconds", "preprocess_seconds",
               "render_seconds", "wall_seconds", "peak_memory_mb", "rmse_srgb8", "rmse_linear", "relative_mse",
               "flip", "luminance_ratio", "fireflies", "rays", "samples_per_second", "non_finite_samples",
               "denoise_seconds"]


@dataclass
class RunSpec:
    label: str
    integrator: str
    params: dict
    spp: int
    time_limit: float = 0.0
    budget: float | None = None   # the equal-time budget this run belongs to


@dataclass
class StudyResult:
    """Everything the reports need."""
    scene: str
    reference_path: str
    reference_meta: dict
    resolution: tuple             # (width, height)
    rows: list                    # dicts keyed by the CSV's columns
    stat_columns: list            # the integrators' own statistics, in CSV order
    difference_scale: float       # sRGB8 error shown as red in every difference image
    output: Path
    files: dict = field(default_factory=dict)  # label -> {'exr', 'png', 'difference'} relative to output
    threads: int = 0              # render threads asked for (0 = all)
    lead_tables: list = field(default_factory=list)  # (title, headers, cells) shown before the others


# -- planning runs -------------------------------------------------------------------------------

def slug(label):
    """A file-name-safe form of a run label."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", label).strip("_") or "run"


def budget_runs(integrators, budgets):
    return [RunSpec(f"{name} {budget:g}s", name, {}, BUDGET_SPP_CAP, budget, budget)
            for name in integrators for budget in budgets]


def table_runs(table):
    """RunSpecs from a parsed --params-file (see the module docstring)."""
    entries = table.get("runs") if isinstance(table, dict) else table
    if not isinstance(entries, list) or not entries:
        raise ValueError("the params file must hold a non-empty list of runs (or {\"runs\": [...]})")
    default_spp = table.get("spp", DEFAULT_TABLE_SPP) if isinstance(table, dict) else DEFAULT_TABLE_SPP
    runs = []
    for index, entry in enumerate(entries):
        if not isinstance(entry, dict) or "integrator" not in entry:
            raise ValueError(f"params file run {index}: needs at least an \"integrator\"")
        params = dict(entry.get("params", {}))
        label = entry.get("label") or f"{entry['integrator']} {json.dumps(params, sort_keys=True)}"
        runs.append(RunSpec(label, entry["integrator"], params, int(entry.get("spp", default_spp)),
                            float(entry.get("time_limit", 0.0))))
    return runs


def check_runs(runs, catalog):
    """Unknown integrators, parameters or out-of-range values are errors: the renderer ignores
    unknown parameters silently, which would make a table row measure something else."""
    by_name = {info["name"]: {p["name"]: p for p in info["params"]} for info in catalog}
    labels = set()
    for run in runs:
        if run.integrator not in by_name:
            raise ValueError(f"{run.label}: unknown integrator '{run.integrator}' (have: {', '.join(by_name)})")
        for name, value in run.params.items():
            declared = by_name[run.integrator].get(name)
            if declared is None:
                raise ValueError(f"{run.label}: '{run.integrator}' has no parameter '{name}'")
            if declared["type"] == "bool":
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"{run.label}: {name} must be a number, got {value!r}")
            if not declared["min"] <= value <= declared["max"]:
                raise ValueError(f"{run.label}: {name} = {value} is outside {declared['min']}..{declared['max']}")
        if run.label == CHECK_LABEL or slug(run.label) in labels:
            raise ValueError(f"run label '{run.label}' is used twice (or clashes with the reference's)")
        labels.add(slug(run.label))


def plan_runs(args, catalog):
    """The runs a `gi study` command line asks for, in order."""
    available = [info["name"] for info in catalog]
    chosen = args.integrators or available
    if args.params_file:
        runs = table_runs(json.loads(Path(args.params_file).read_text()))
        if args.integrators:
            runs = [run for run in runs if run.integrator in chosen]
    else:
        unknown = sorted(set(chosen) - set(available))
        if unknown:
            raise ValueError(f"unknown integrator(s) {', '.join(unknown)} (have: {', '.join(available)})")
        runs = budget_runs(chosen, args.budgets or DEFAULT_BUDGETS)
    check_runs(runs, catalog)
    if not runs:
        raise ValueError("no runs: --integrators selects none of the params file's runs")
    return runs


# -- the reference ---------------------------------------------------------------------------------

def load_reference(path):
    """(linear RGB float32 (H, W, 3), metadata) of a reference EXR."""
    from .render import require_core
    pixels, meta = require_core().read_image(str(path))
    channels = meta.get("channels", [])
    if pixels.ndim != 3 or pixels.shape[2] < 3 or (channels and channels[:3] != ["R", "G", "B"]):
        raise ValueError(f"{path}: expected R, G, B as the first channels, got {channels or pixels.shape}")
    return np.ascontiguousarray(pixels[..., :3], dtype=np.float32), meta


def study_resolution(requested, reference):
    """The reference's size; a --resolution that differs is an error, not a resample."""
    height, width = reference.shape[:2]
    if requested and tuple(requested) != (width, height):
        raise ValueError(f"--resolution {requested[0]} {requested[1]} does not match the reference's "
                         f"{width}x{height}")
    return width, height


# -- one run -------------------------------------------------------------------------------------

def reset_peak_memory():
    """Restarts the kernel's resident-memory high-water mark (Linux), so the next peak is one run's."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
        return True
    except OSError:
        return False


def peak_memory_bytes(fallback):
    """This process's peak resident memory since the last reset (VmHWM), else the renderer's figure."""
    try:
        match = re.search(r"VmHWM:\s+(\d+)\s+kB", Path("/proc/self/status").read_text())
    except OSError:
        match = None
    return int(match.group(1)) * 1024 if match else int(fallback)


def integrator_stats(stats):
    return {key: value for key, value in stats.items() if key not in COMMON_STATS}


def measured_row(run, result, wall_seconds, peak_bytes, reference, denoised=None, denoise_seconds=0.0):
    """The CSV row of one run: cost, error metrics (fireflies against the reference, see
    metrics.firefly_count) and the integrator's statistics. With `denoised` (its colour denoised in
    denoise_seconds): the run's denoised row, its time the render's plus the denoising's."""
    stats = result.stats
    color = np.asarray(result.color) if denoised is None else denoised
    scores = metrics.compare(color, reference)
    return {"label": run.label, "integrator": run.integrator,
            "budget_seconds": "" if run.budget is None else run.budget, "spp": result.spp,
            "params": json.dumps(run.params, sort_keys=True), "seconds": stats["seconds"] + denoise_seconds,
            "preprocess_seconds": stats["preprocess_seconds"], "render_seconds": stats["render_seconds"],
            "denoise_seconds": denoise_seconds if denoised is not None else "",
            "wall_seconds": wall_seconds + denoise_seconds, "peak_memory_mb": peak_bytes / 2 ** 20,
            "rmse_srgb8": scores.rmse_srgb8, "rmse_linear": scores.rmse_linear,
            "relative_mse": scores.relative_mse, "flip": scores.flip,
            "luminance_ratio": scores.luminance_ratio, "fireflies": scores.fireflies,
            "rays": int(stats["rays"]), "samples_per_second": stats["samples_per_second"],
            "non_finite_samples": int(stats["non_finite_samples"]), **integrator_stats(stats)}


def check_row(reference, meta):
    """The reference scored against itself: a run whose every error must come out 0."""
    scores = metrics.compare(reference, reference)
    seconds = float(meta.get("gi:seconds", "nan"))
    return {"label": CHECK_LABEL, "integrator": meta.get("gi:integrator", "reference"), "budget_seconds": "",
            "spp": meta.get("gi:spp", ""), "params": meta.get("gi:params", ""), "seconds": seconds,
            "preprocess_seconds": 0.0, "render_seconds": seconds, "wall_seconds": seconds,
            "peak_memory_mb": "", "rmse_srgb8": scores.rmse_srgb8, "rmse_linear": scores.rmse_linear,
            "relative_mse": scores.relative_mse, "flip": scores.flip,
            "luminance_ratio": scores.luminance_ratio, "fireflies": scores.fireflies,
            "rays": "", "samples_per_second": "", "non_finite_samples": ""}


def render_run(loaded, run, resolution, seed, threads):
    """(result, wall seconds, peak memory bytes) of one run on the already loaded scene."""
    from .render import render_loaded, render_settings
    settings = render_settings(loaded, run.integrator, run.params, run.spp, seed, threads, run.time_limit,
                               resolution, "box")
    reset_peak_memory()
    start = time.perf_counter()
    result = render_loaded(loaded, settings, run.label)
    wall_seconds = time.perf_counter() - start
    return result, wall_seconds, peak_memory_bytes(result.stats["peak_memory_bytes"])


def save_run(result, run, output, scene, denoised=None, denoise_meta=None):
    """The run's EXR and display PNG (of `denoised` when given: the EXR keeps the raw colour as
    noisy.R/G/B); returns their paths relative to the output folder."""
    from .render import require_core
    core = require_core()
    name = slug(run.label)
    files = {"exr": f"runs/{name}.exr", "png": f"runs/{name}.png", "difference": f"runs/{name}_difference.png"}
    meta = {"gi:scene": str(scene), "gi:integrator": run.integrator, "gi:label": run.label,
            "gi:params": json.dumps(run.params, sort_keys=True), "gi:spp": str(result.spp),
            "gi:seconds": f"{result.stats['seconds']:.3f}", **(denoise_meta or {})}
    color = np.asarray(result.color) if denoised is None else denoised
    layers = {} if denoised is None else {"noisy": np.asarray(result.color)}
    core.write_exr(str(output / files["exr"]), result, meta, color=color, layers=layers)
    core.write_png(str(output / files["png"]), color)
    return files


def denoised_run(run):
    """The RunSpec naming a run's denoised row."""
    return RunSpec(run.label + DENOISED_SUFFIX, run.integrator + DENOISED_SUFFIX, run.params, run.spp,
                   run.time_limit, run.budget)


def study_denoiser(requested, threads):
    """(a gi._core.Denoiser or None, the integrators to denoise). `requested`: None for the default
    (DEFAULT_DENOISED, skipped with a warning without Open Image Denoise), [] for none, else a list
    that needs Open Image Denoise (DenoiserMissing otherwise)."""
    from .errors import warn
    from .denoise import open_denoiser
    if requested == []:
        return None, []
    try:
        return open_denoiser(threads), list(requested if requested is not None else DEFAULT_DENOISED)
    except DenoiserMissing as error:
        if requested is not None:
            raise
        warn(f"no denoised rows: {error}")
        return None, []


# -- difference images ---------------------------------------------------------------------------

def shared_difference_scale(colors, reference):
    """One red point for every difference image, so that their colours compare across runs: the
    largest of the runs' own scales (each the 99th percentile of its sRGB8 error)."""
    scales = [metrics.difference_image(color, reference)[1] for color in colors]
    return max(scales, default=1.0)


def write_difference_images(colors, reference, output, files):
    """Writes every run's difference image; returns the shared scale."""
    from matplotlib import image as mpimg
    scale = shared_difference_scale(colors.values(), reference)
    for label, color in colors.items():
        picture, _ = metrics.difference_image(color, reference, max_error=scale)
        mpimg.imsave(output / files[label]["difference"], picture)
    return scale


# -- the study -----------------------------------------------------------------------------------

def stat_columns(rows):
    """The integrators' own statistics, in first-seen order (rows without one leave it empty)."""
    columns = []
    for row in rows:
        columns += [key for key in row if key not in RUN_COLUMNS and key not in columns]
    return columns


def write_csv(path, rows, extra_columns):
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=RUN_COLUMNS + extra_columns, restval="")
        writer.writeheader()
        writer.writerows(rows)


def progress_line(row):
    budget = f" of {row['budget_seconds']:g} s" if row["budget_seconds"] != "" else ""
    return (f"{row['label']}: {row['seconds']:.2f} s{budget} ({row['preprocess_seconds']:.2f} s preprocessing), "
            f"{row['spp']} spp, RMSE sRGB8 {row['rmse_srgb8']:.2f}, FLIP {row['flip']:.4f}")


def run_study(scene, reference_path, runs, output, resolution=None, seed=0, threads=0, camera=None,
              show_progress=False, log=print, denoise=None, lead_tables=None):
    """Renders every run, scores it against the reference, writes everything; returns a StudyResult.
    denoise: the integrators whose runs also get a denoised row (see study_denoiser). lead_tables:
    rows -> [(title, headers, cells)], tables the reports show first (e.g. gi.thesis's)."""
    from .denoise import denoise_metadata, denoise_result
    from tqdm import tqdm

    from .render import require_core
    from .loader import load_stage
    from .report import write_reports
    reference, meta = load_reference(reference_path)
    size = study_resolution(resolution, reference)
    denoiser, denoised_integrators = study_denoiser(denoise, threads)
    # The reference's camera, unless told otherwise: a study against another view measures nothing.
    loaded = load_stage(str(scene), camera=camera or meta.get("gi:camera") or None)
    output = Path(output)
    (output / "runs").mkdir(parents=True, exist_ok=True)
    rows, colors, files = [check_row(reference, meta)], {}, {}
    for run in tqdm(runs, desc="study", disable=not show_progress, leave=False, file=sys.stderr):
        result, wall_seconds, peak_bytes = render_run(loaded, run, size, seed, threads)
        rows.append(measured_row(run, result, wall_seconds, peak_bytes, reference))
        colors[run.label] = np.array(result.color)
        files[run.label] = save_run(result, run, output, scene)
        log(progress_line(rows[-1]))
        if run.integrator in denoised_integrators:
            denoised = denoised_run(run)
            reset_peak_memory()
            color, seconds = denoise_result(denoiser, result)
            peak_bytes = max(peak_bytes, peak_memory_bytes(0))
            rows.append(measured_row(denoised, result, wall_seconds, peak_bytes, reference, color, seconds))
            colors[denoised.label] = color
            files[denoised.label] = save_run(result, denoised, output, scene, color,
                                             denoise_metadata(denoiser, seconds))
            log(progress_line(rows[-1]))
        # Written after every run, so that a run that crashes the process leaves the others' results.
        write_csv(output / "results.csv", rows, stat_columns(rows))
    require_core().write_png(str(output / "reference.png"), reference)
    scale = write_difference_images(colors, reference, output, files)
    study = StudyResult(str(scene), str(reference_path), meta, size, rows, stat_columns(rows), scale, output,
                        files, threads, lead_tables(rows[1:]) if lead_tables else [])
    write_reports(study)
    return study


def denoise_choice(text, runs):
    """--denoise as run_study takes it: None (not given: the default), [] for 'none', else the listed
    integrators, each of which must have runs."""
    if text is None:
        return None
    names = [name.strip() for name in text.split(",") if name.strip()]
    if names == ["none"]:
        return []
    missing = sorted(set(names) - {run.integrator for run in runs})
    if not names or missing:
        raise ValueError(f"--denoise {text}: {', '.join(missing) or 'nothing'} is not among the study's integrators")
    return names


def cmd_study(args):
    from .render import require_core
    if args.thesis:
        from .thesis import cmd_thesis_study
        return cmd_thesis_study(args)
    if args.spp is not None or args.reference_seconds is not None:
        raise ValueError("--spp and --reference-seconds belong to --thesis (a params file sets each run's spp)")
    if not args.scene or not args.reference:
        raise ValueError("gi study needs a scene and --reference (or --thesis caixa|sibenik)")
    runs = plan_runs(args, require_core().integrators())
    study = run_study(args.scene, args.reference, runs, args.output, args.resolution, args.seed, args.threads,
                      args.camera, show_progress=sys.stderr.isatty(), denoise=denoise_choice(args.denoise, runs))
    print(f"{len(runs)} runs -> {study.output}/results.csv, {study.output}/report.html")
    return 0
