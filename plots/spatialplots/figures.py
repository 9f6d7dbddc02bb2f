"""Shared drawing helpers: figure grids, legends, atomic PNG writes, the run caption every
figure carries, and the panels several figure families draw (complexity curves, accuracy/time
trade-offs with a Pareto front).

Run captions.  save_atomically adds a footer strip to every figure naming the run(s) its rows
come from (`run: <id>`; up to RUNS_LISTED ids listed; more as `<count> runs: <first> ... <last>`,
ordered by the ids' timestamps).  A family passes the rows it drew (`rows=`); without them the
rows of the family being drawn are used (the command line sets them with family_rows()).  The
run ids of every figure written are also kept (figure_runs()) for the paper's captions."""

import math
import os
import re
import tempfile

import matplotlib.pyplot as plt
import numpy as np

from . import formats
from .core import (COMPLEXITY_FUNCTIONS, METRIC_LABELS, fastest_series, fit_exponent,
                   median, pareto_front, structure_of)

SUBPLOT_INCHES = (5.0, 4.0)
DPI = 120
MAX_COLUMNS = 3
# PDF: embed TrueType (Type 42) fonts instead of Type 3, which print and search properly.
PRINT_SETTINGS = {"pdf.fonttype": 42}
LEGEND_COLUMNS = 2

_UMASK = os.umask(0)
os.umask(_UMASK)

RUNS_LISTED = 3  # a caption lists this many run ids; more are summarised as count, first, last
FOOTER_INCHES = 0.26
FOOTER_FONT_SIZE = 7
FOOTER_COLOUR = "dimgrey"
_STAMP = re.compile(r"\d{8}T\d{6}Z")  # the UTC timestamp inside a run id
_family_rows = []  # the rows of the family being drawn: the caption's default
_figure_runs = {}  # figure file name (no extension) -> run ids, of every figure written


# -------------------------------------------------------------------------------- figures

def grid_shape(count):
    columns = min(MAX_COLUMNS, count)
    rows = int(math.ceil(count / columns))
    return rows, columns


def legend_inches(entries, columns=LEGEND_COLUMNS):
    """Height to reserve under a subplot for a legend of `entries` entries."""
    return 0.2 * math.ceil(entries / columns) + (0.3 if entries else 0)


def new_figure(count, legend_entries=0, one_column=False):
    """A grid of `count` subplots; legend_entries reserves room for a legend under each.
    one_column stacks them (wide legends of many series then do not run into each other)."""
    rows, columns = (count, 1) if one_column else grid_shape(count)
    width_scale = 2.0 if one_column else 1.0
    figure, axes = plt.subplots(
        rows, columns, squeeze=False,
        figsize=(SUBPLOT_INCHES[0] * columns * width_scale,
                 (SUBPLOT_INCHES[1] + legend_inches(legend_entries)) * rows + 0.6))
    axes = axes.ravel()
    for extra in axes[count:]:
        extra.set_visible(False)
    return figure, axes[:count]


def finish_figure(figure, title):
    """Figure title above the subplots' own titles, then a tight layout under it."""
    figure.suptitle(title)
    lines = title.count("\n") + 1
    top = 1.0 - (0.5 + 0.25 * (lines - 1)) / figure.get_figheight()  # half an inch a line
    figure.tight_layout(rect=(0, 0, 1, top))


# -------------------------------------------------------------------------------- run captions

def run_ids(rows):
    """The distinct run ids of rows (Row objects or run-id strings), oldest first (by the
    timestamp in the id, then by the id)."""
    ids = {row if isinstance(row, str) else row.run_id for row in rows} - {""}

    def when(run_id):
        found = _STAMP.search(run_id)
        return (found.group(0) if found else "", run_id)
    return sorted(ids, key=when)


def runs_caption(ids):
    """The footer text naming the runs: 'run: a', 'runs: a, b', or '5 runs: a ... e'."""
    ids = list(ids)
    if not ids:
        return "runs: not recorded"
    if len(ids) <= RUNS_LISTED:
        return ("run: " if len(ids) == 1 else "runs: ") + ", ".join(ids)
    return f"{len(ids)} runs: {ids[0]} \u2026 {ids[-1]}"


def family_rows(rows):
    """Set the rows a caption names when a family saves a figure without rows=."""
    _family_rows[:] = list(rows)


def forget_runs():
    """Start a new record of figure runs (one per command-line run)."""
    _figure_runs.clear()


def figure_runs():
    """{figure name without extension: [run ids]} of every figure written so far."""
    return {name: list(ids) for name, ids in _figure_runs.items()}


def add_footer(figure, text):
    """Grow the figure by a strip at the bottom and write text in it; the axes and figure
    texts keep their size and place (measured from the top)."""
    height = figure.get_figheight()
    grown = height + FOOTER_INCHES
    scale, lift = height / grown, FOOTER_INCHES / grown
    for axis in figure.axes:
        box = axis.get_position()
        axis.set_position([box.x0, box.y0 * scale + lift, box.width, box.height * scale])
    for label in figure.texts:
        x, y = label.get_position()
        label.set_position((x, y * scale + lift))
    figure.set_figheight(grown)
    figure.text(0.006, 0.45 * FOOTER_INCHES / grown, text, ha="left", va="center",
                fontsize=FOOTER_FONT_SIZE, color=FOOTER_COLOUR)


def save_atomically(figure, path, rows=None):
    """Write the figure in every chosen format (formats.py: path's .png, and/or a vector .pdf
    beside it), each to a temp file in the same directory renamed over the target, with a
    footer naming the runs of `rows` (default: the family's rows, family_rows()).  Returns the
    first file written."""
    ids = run_ids(_family_rows if rows is None else rows)
    _figure_runs[os.path.splitext(os.path.basename(path))[0]] = ids
    try:
        add_footer(figure, runs_caption(ids))
        written = [_write_one(figure, target) for target in formats.paths(path)]
    finally:
        plt.close(figure)
    return written[0]


def _write_one(figure, path):
    directory = os.path.dirname(os.path.abspath(path))
    kind = path.rsplit(".", 1)[-1]
    handle, temp_path = tempfile.mkstemp(
        prefix="." + os.path.basename(path) + ".", suffix=".tmp", dir=directory)
    try:
        with os.fdopen(handle, "wb") as stream, plt.rc_context(PRINT_SETTINGS):
            figure.savefig(stream, format=kind, dpi=DPI)
        os.chmod(temp_path, 0o666 & ~_UMASK)  # mkstemp makes 0600; give a normal file's mode
        os.replace(temp_path, path)
    except BaseException:
        try:
            os.unlink(temp_path)
        except OSError:
            pass
        raise
    print(f"wrote {path}")
    return path


# -------------------------------------------------------------------------------- axes

def legend_below(axis, **options):
    """Legend under the axes, so it never hides a curve."""
    settings = dict(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=LEGEND_COLUMNS,
                    fontsize="small", frameon=False)
    settings.update(options)
    axis.legend(**settings)


def log_log_grid(axis, log_y=True):
    """Log-log (or log-x) axes with major and faint minor grid lines."""
    axis.set_xscale("log")
    if log_y:
        axis.set_yscale("log")
    axis.grid(True, which="major", alpha=0.5)
    axis.grid(True, which="minor", alpha=0.15)


def empty_panel(axis, text):
    """A panel without data: no axes, only the reason."""
    axis.set_axis_off()
    axis.text(0.5, 0.5, text, ha="center", va="center")


def plot_series(axis, xs, ys, style_of, validated, styles, **options):
    """One line with markers in the style of the label `style_of` (the legend text is the
    `label` option); unvalidated series hollow and dashed."""
    colour, marker = styles(style_of)
    settings = dict(marker=marker, color=colour, linestyle="-" if validated else "--",
                    markerfacecolor=colour if validated else "none")
    settings.update(options)
    return axis.plot(xs, ys, **settings)


def bars(axis, xs, heights, width, label, colour, validated, **options):
    """Bars of one series; unvalidated ones hatched and unfilled."""
    return axis.bar(xs, heights, width, label=label, color=colour, edgecolor=colour,
                    fill=validated, hatch=None if validated else "//", **options)


def emphasise(axis, structure):
    """Thicker lines for the series of `structure` (the one a target is about)."""
    for line in axis.get_lines():
        if structure_of(line.get_label()) == structure:
            line.set_linewidth(2.5)
            line.set_zorder(4)


# -------------------------------------------------------------------------------- panels

def draw_complexity_panel(axis, series_by_key, operation, metric, unit, workload, styles,
                          registry, suite):
    """Log-log time against n, one line per (label, validated) series with its fitted exponent
    in the legend, and a grey dashed theory line.  The theory is the registry's complexity of
    the series the line is anchored at: the smallest-n point of the fastest validated series
    among those whose theory is the panel's reference (Registry.reference_theory)."""
    series = {key: {n: median(values) for n, values in points.items()}
              for key, points in series_by_key.items()}
    for label, validated in sorted(series, key=lambda key: (key[0], not key[1])):
        points = series[(label, validated)]
        ns = np.array(sorted(points), dtype=float)
        times = np.array([points[n] for n in sorted(points)])
        exponent = fit_exponent(ns, times)
        text = label + ("" if validated else " [unvalidated]")
        text += f" (n^{exponent:.2f})" if math.isfinite(exponent) else " (one n)"
        plot_series(axis, ns, times, label, validated, styles, label=text)

    def theory(key):
        return registry.theory_for(operation, metric, structure_of(key[0]))

    candidates = {key: points for key, points in series.items() if key[1]} or series
    reference = registry.reference_theory(suite, operation, metric,
                                          sorted({structure_of(key[0]) for key in series}))
    candidates = {key: p for key, p in candidates.items() if theory(key) == reference} or candidates
    fastest = fastest_series(candidates)
    anchor_n = min(candidates[fastest])
    anchor_t = candidates[fastest][anchor_n]
    complexity = theory(fastest)
    function = COMPLEXITY_FUNCTIONS.get(complexity)
    all_n = sorted({n for points in series.values() for n in points if n >= anchor_n})
    if function is not None and len(all_n) >= 2:
        ns = np.array(all_n, dtype=float)
        base = float(function(np.array([float(anchor_n)]))[0])
        if base > 0 and math.isfinite(base):
            axis.plot(ns, anchor_t * function(ns) / base, color="grey", linestyle="--",
                      linewidth=1.2, label=f"theory O({complexity})", zorder=1)

    log_log_grid(axis)
    axis.set_title(workload)
    axis.set_xlabel("n (objects)")
    axis.set_ylabel(f"{METRIC_LABELS.get(metric, metric)} ({unit})")
    legend_below(axis)


def draw_tradeoff_panel(axis, points, xlabel, ylabel, title, log_y=True):
    """Scatter of (label, x, y) points, both axes to be minimised: the Pareto front starred
    and joined by a dashed step line, every point labelled."""
    xy = [(x, y) for _, x, y in points]
    front = set(pareto_front(xy))
    cmap = plt.get_cmap("tab20")
    for i, (label, x, y) in enumerate(points):
        on_front = i in front
        axis.scatter([x], [y], color=cmap(i % 20), marker="*" if on_front else "o",
                     s=90 if on_front else 30, zorder=3,
                     edgecolors="black" if on_front else "none")
        axis.annotate(label, (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
    if front:
        fx = [xy[i][0] for i in sorted(front, key=lambda i: xy[i][0])]
        fy = [xy[i][1] for i in sorted(front, key=lambda i: xy[i][0])]
        axis.step(fx, fy, where="post", color="black", linewidth=1, linestyle="--",
                  label="Pareto front (stars)", zorder=2)
        axis.legend(fontsize="small", loc="upper right")
    axis.set_xscale("log")
    if log_y:
        axis.set_yscale("log")
    axis.set_xlabel(xlabel)
    axis.set_ylabel(ylabel)
    axis.set_title(title, fontsize="medium")
    axis.grid(True, which="both", alpha=0.3)
