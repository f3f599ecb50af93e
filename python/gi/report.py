"""The study's plot and reports: error_vs_time.png, report.md and a self-contained report.html.

Tables follow the thesis's form (tables 4.4, 4.8, ...): one row per technique, one column per metric,
one table per equal-time budget (or one for a parameter table); with several budgets, a technique x
budget table of RMSE sRGB8 too. Images are shown side by side: reference, render, difference.
"""
from __future__ import annotations

import base64
import html
import math
import os
import platform
from collections import defaultdict
from pathlib import Path

import numpy as np

from . import metrics
from .study import DENOISED_SUFFIX

PLOT = "error_vs_time.png"
PALETTE = "difference_palette.png"
REFERENCE_PNG = "reference.png"

# (header, row key, format) of the technique x metric tables.
METRIC_COLUMNS = [("time s", "seconds", ".2f"), ("preprocess s", "preprocess_seconds", ".2f"),
                  ("render s", "render_seconds", ".2f"), ("spp", "spp", "d"),
                  ("peak MB", "peak_memory_mb", ".0f"), ("RMSE sRGB8", "rmse_srgb8", ".2f"),
                  ("RMSE linear", "rmse_linear", ".4f"), ("rel. MSE", "relative_mse", ".4g"),
                  ("FLIP", "flip", ".4f"), ("lum. ratio", "luminance_ratio", ".3f"),
                  ("fireflies", "fireflies", "d")]
# Equal-time tables also show the budget and the wall time around the render call, beside "time s"
# (the render's own measure, preprocessing included).
BUDGET_COLUMNS = [("budget s", "budget_seconds", "g")]
WALL_COLUMNS = [("wall s", "wall_seconds", ".2f")]


def number(value, spec=None):
    """A cell: formatted numbers (whole numbers as integers unless spec says otherwise), '' for
    missing values, text as it is."""
    if value is None or value == "":
        return ""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(x):
        return str(x)
    if spec == "d" or (spec is None and x.is_integer() and abs(x) < 1e15):
        return format(int(round(x)), "d")
    return format(x, spec or ".4g")


# -- tables as (title, headers, cells) -------------------------------------------------------------

def runs_of(study):
    """The rendered runs (the reference check row excluded)."""
    return study.rows[1:]


def groups(study):
    """(title, rows) per equal-time budget (its title with the range of measured seconds), or one
    group for a parameter table."""
    by_budget = defaultdict(list)
    for row in runs_of(study):
        by_budget[row["budget_seconds"]].append(row)
    result = []
    for budget, rows in by_budget.items():
        if budget == "":
            result.append(("Fixed parameters", rows))
            continue
        seconds = [float(row["seconds"]) for row in rows]
        result.append((f"Equal time: {number(budget, 'g')} s (measured {min(seconds):.2f}-{max(seconds):.2f} s)",
                       rows))
    return result


def technique(row):
    """In an equal-time table the integrator names the row; in a parameter table, the run's label."""
    return row["integrator"] if row["budget_seconds"] != "" else row["label"]


def metric_columns(rows):
    """METRIC_COLUMNS, with the budget and the wall time beside the measured time at equal time."""
    if any(row["budget_seconds"] == "" for row in rows):
        return METRIC_COLUMNS
    return BUDGET_COLUMNS + METRIC_COLUMNS[:1] + WALL_COLUMNS + METRIC_COLUMNS[1:]


def metric_table(title, rows):
    columns = metric_columns(rows)
    headers = ["technique"] + [header for header, _, _ in columns]
    cells = [[technique(row)] + [number(row[key], spec) for _, key, spec in columns] for row in rows]
    return title, headers, cells


def reference_table(study):
    meta, check = study.reference_meta, study.rows[0]
    headers = ["reference", "spp", "seconds", "rel. std. error of mean", "pixel rel. std. error",
               "its noise, sRGB8 codes", "RMSE sRGB8 vs itself", "FLIP vs itself"]
    cells = [[Path(study.reference_path).name, meta.get("gi:spp", ""), meta.get("gi:seconds", ""),
              meta.get("gi:relative_standard_error", ""), meta.get("gi:pixel_relative_standard_error", ""),
              number(meta.get("gi:srgb8_standard_error", ""), ".2f"),
              number(check["rmse_srgb8"], ".2f"), number(check["flip"], ".4f")]]
    return "Reference", headers, cells


def rmse_by_budget_table(study):
    """Technique x budget RMSE sRGB8, the shape of the thesis's RMSE tables; None without budgets."""
    budgets = sorted({row["budget_seconds"] for row in runs_of(study) if row["budget_seconds"] != ""})
    if len(budgets) < 2:
        return None
    value = {(row["integrator"], row["budget_seconds"]): row["rmse_srgb8"] for row in runs_of(study)}
    techniques = list(dict.fromkeys(row["integrator"] for row in runs_of(study)))
    cells = [[name] + [number(value.get((name, b)), ".2f") for b in budgets] for name in techniques]
    return "RMSE sRGB8 (0-255) by budget", ["technique"] + [f"{number(b, 'g')} s" for b in budgets], cells


def stats_table(study):
    """The integrators' own statistics (records, photons, ...); None when no integrator has any."""
    columns = [c for c in study.stat_columns if any(row.get(c, "") != "" for row in runs_of(study))]
    if not columns:
        return None
    cells = [[row["label"]] + [number(row.get(c, "")) for c in columns] for row in runs_of(study)
             if any(row.get(c, "") != "" for c in columns)]
    return "Integrator statistics", ["technique"] + columns, cells


def all_tables(study):
    tables = study.lead_tables + [reference_table(study)]
    tables += [metric_table(title, rows) for title, rows in groups(study)]
    return tables + [t for t in (rmse_by_budget_table(study), stats_table(study)) if t]


# -- the plot ------------------------------------------------------------------------------------

def plain_log_formatter():
    """Matplotlib's choice of which log ticks to label, written 0.5, 1, 2 rather than 5x10^-1."""
    from matplotlib.ticker import LogFormatterSciNotation

    class PlainLogFormatter(LogFormatterSciNotation):
        def __call__(self, value, pos=None):
            return f"{value:g}" if super().__call__(value, pos) else ""
    return PlainLogFormatter


def plot_error_vs_time(study, path):
    """Log-log RMSE (sRGB8 and linear) against total seconds, one line per integrator."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib import pyplot as plt

    figure, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    by_integrator = defaultdict(list)
    for row in runs_of(study):
        by_integrator[row["integrator"]].append(row)
    # A technique's denoised rows share its colour, dashed.
    colours = {}
    for integrator in by_integrator:
        colours.setdefault(integrator.removesuffix(DENOISED_SUFFIX), f"C{len(colours) % 10}")
    for axis, key, name in zip(axes, ("rmse_srgb8", "rmse_linear"), ("RMSE sRGB8 (0-255)", "RMSE linear")):
        for integrator, rows in by_integrator.items():
            # Log axes cannot show 0 (a run identical to the reference); leave such points out.
            points = sorted((r["seconds"], r[key]) for r in rows if r["seconds"] > 0 and r[key] > 0)
            if points:
                base = integrator.removesuffix(DENOISED_SUFFIX)
                axis.plot(*zip(*points), marker="o", label=integrator, color=colours[base],
                          linestyle="-" if integrator == base else "--")
        axis.set(xscale="log", yscale="log", xlabel="time (s)", ylabel=name, title=name)
        for ticks in (axis.xaxis, axis.yaxis):
            ticks.set_major_formatter(plain_log_formatter()())
            ticks.set_minor_formatter(plain_log_formatter()(labelOnlyBase=False))
        axis.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize="small")
    figure.suptitle(f"{Path(study.scene).name}: error against time")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def write_palette(path, width=256, height=16):
    """The difference images' colour scale as a strip, black (0) to red (the shared scale)."""
    from matplotlib import image as mpimg
    strip = metrics.palette(np.linspace(0.0, 1.0, width))
    mpimg.imsave(path, np.repeat(strip[np.newaxis], height, axis=0))


# -- Markdown ------------------------------------------------------------------------------------

def markdown_table(title, headers, cells):
    lines = [f"### {title}", "", "| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in cells]
    return "\n".join(lines) + "\n"


def cpu_model():
    """The CPU's model name (Linux's /proc/cpuinfo), else what the platform module knows."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown CPU"


def machine_line(study):
    """The machine the figures were measured on, and what kind of figures they are."""
    available = os.cpu_count() or 0
    threads = study.threads if study.threads > 0 else available
    return (f"Measured on {cpu_model()}, {threads} render threads ({available} hardware threads). Every figure "
            f"comes from one run of each technique (one seed, one timing): read them as ratios between "
            f"techniques on this machine, not as absolute times or errors.")


def summary_line(study, code=lambda text: f"`{text}`"):
    width, height = study.resolution
    return (f"Scene {code(study.scene)} at {width}x{height}, against {code(study.reference_path)} "
            f"({study.reference_meta.get('gi:spp', '?')} spp).")


def palette_caption(study):
    return (f"Difference images: mean absolute sRGB8 difference per pixel, black (0) -> green -> yellow -> "
            f"red ({study.difference_scale:.1f} and above), the same scale for every run.")


def markdown_report(study):
    parts = ["# Integrator study", "", summary_line(study), "", machine_line(study), ""]
    parts += [markdown_table(*table) for table in all_tables(study)]
    parts += ["## Error against time", "", f"![error against time]({PLOT})", "", "## Images", "",
              palette_caption(study), "", f"![palette]({PALETTE})", "",
              "| run | reference | render | difference |", "|---|---|---|---|"]
    for row in runs_of(study):
        files = study.files[row["label"]]
        parts.append(f"| {row['label']} (RMSE sRGB8 {number(row['rmse_srgb8'], '.2f')}) "
                     f"| ![reference]({REFERENCE_PNG}) | ![render]({files['png']}) "
                     f"| ![difference]({files['difference']}) |")
    return "\n".join(parts) + "\n"


# -- HTML ----------------------------------------------------------------------------------------

STYLE = """
body { font-family: sans-serif; margin: 2em; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th:first-child, td:first-child { text-align: left; }
th { background: #f0f0f0; }
.run { display: flex; gap: 1em; margin-bottom: 1.5em; align-items: flex-start; }
figure { margin: 0; }
figure img { width: 256px; image-rendering: pixelated; }
figcaption { font-size: 0.85em; }
img.palette { width: 256px; height: 16px; image-rendering: pixelated; }
"""


def inline_png(path):
    """A data: URI, so that report.html is one self-contained file."""
    return "data:image/png;base64," + base64.b64encode(Path(path).read_bytes()).decode("ascii")


def html_table(title, headers, cells):
    head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in cells)
    return f"<h3>{html.escape(title)}</h3>\n<table><tr>{head}</tr>{body}</table>\n"


def html_figure(source, caption):
    return (f'<figure><img src="{source}" alt="{html.escape(caption)}">'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>")


def html_run(study, row, reference_uri):
    files = study.files[row["label"]]
    caption = (f"{row['label']}: {number(row['seconds'], '.2f')} s, {row['spp']} spp, "
               f"RMSE sRGB8 {number(row['rmse_srgb8'], '.2f')}, FLIP {number(row['flip'], '.4f')}")
    return ('<div class="run">' + html_figure(reference_uri, "reference")
            + html_figure(inline_png(study.output / files["png"]), caption)
            + html_figure(inline_png(study.output / files["difference"]), f"difference: {row['label']}")
            + "</div>\n")


def html_report(study):
    reference_uri = inline_png(study.output / REFERENCE_PNG)
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>Integrator study</title>",
             f"<style>{STYLE}</style></head><body>", "<h1>Integrator study</h1>",
             f"<p>{summary_line(study, code=lambda text: f'<code>{html.escape(text)}</code>')}</p>",
             f"<p>{html.escape(machine_line(study))}</p>"]
    parts += [html_table(*table) for table in all_tables(study)]
    parts += ["<h2>Error against time</h2>", f'<img src="{inline_png(study.output / PLOT)}" alt="error against time">',
              "<h2>Images</h2>", f"<p>{html.escape(palette_caption(study))}</p>",
              f'<p><img class="palette" src="{inline_png(study.output / PALETTE)}" alt="palette"></p>']
    parts += [html_run(study, row, reference_uri) for row in runs_of(study)]
    parts.append("</body></html>\n")
    return "\n".join(parts)


def write_reports(study):
    """error_vs_time.png, difference_palette.png, report.md and report.html in the study's folder."""
    plot_error_vs_time(study, study.output / PLOT)
    write_palette(study.output / PALETTE)
    (study.output / "report.md").write_text(markdown_report(study))
    (study.output / "report.html").write_text(html_report(study))
