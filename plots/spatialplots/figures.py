"""Shared drawing helpers: figure grids, legends, atomic PNG writes, and the panels several
figure families draw (complexity curves, accuracy/time trade-offs with a Pareto front)."""

import math
import os
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


def save_atomically(figure, path):
    """Write the figure in every chosen format (formats.py: path's .png, and/or a vector .pdf
    beside it), each to a temp file in the same directory renamed over the target.  Returns
    the first file written."""
    try:
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
