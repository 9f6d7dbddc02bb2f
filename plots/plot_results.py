#!/usr/bin/python3
"""Plot spatialbench results: read results/*.csv, write PNGs.

Run with Debian's interpreter (it sees python3-matplotlib and python3-numpy):

    /usr/bin/python3 plots/plot_results.py [--results DIR] [--out DIR] [--include-unvalidated]

Input: only the tidy CSV tables in --results (default <repo>/results), one figure per row with
the columns
    suite,structure,bv,workload,n,dim,scalar,operation,params,metric,value,unit,validated,run_id
(extra columns after them are ignored; a `bv` of "-" means none, like an empty one).  Files
that are missing, empty, lack these columns, or hold malformed rows are skipped with a message;
so are suites not listed in SUITES below.

Output, in --out (default <repo>/plots), each PNG written atomically (temp file + os.replace):

1. Complexity curves, <suite>_<operation>[_<params>]_<dim>d_<scalar>.png (suffix _<metric>
   when an operation has several time metrics): one subplot per workload, log-log time
   (time_per_op or build_time) against n, one line per structure.  The legend gives the
   least-squares slope of log(time) on log(n) ("kd_tree (n^0.12)"); a grey dashed line shows the
   theoretical complexity from THEORY, anchored at the smallest-n point of the fastest structure
   (fastest at the largest n all structures share; trees are preferred over linear scans, so a
   trivially fast brute-force "build" does not turn the n log n line into an n line).
2. Accuracy against time, <suite>_recall_vs_time_<workload>_<dim>d_<scalar>.png: for
   operation approx_knn, recall against time_per_op at the largest n, one curve per structure
   through its eps values (each point labelled with its eps).
3. Ray casting, raycast_time_per_ray.png: one subplot per ray kind (params), log-log time per ray
   against n (triangles), colour = structure, line style = generated mesh workload (sphere solid,
   soup dashed; legend with the fitted exponent), real meshes as unconnected crosses at their n.
4. Ratios, <suite>_ratios.png, when time_ratio rows exist: bars of kd_tree's time divided by
   each peer's time per (operation, params), one subplot per (workload, dim, scalar), each peer
   at the largest n it was measured at, with a line at 1.0 (log y axis when the ratios span
   more than a decade).
5. Bounding volumes and the BVH: bv_tradeoff.png (bv suite) and bvh_tradeoff.png (raycast suite).
6. Collision (collide suite; its rows and the scenes suite's are left out of 1, see
   OWN_FIGURE_SUITES): collide_boxes.png (workload boxes: build + all pairs against n, log-log
   with fitted exponents, and the speed-up time(cgal_box_intersection) / time at each n with the
   5x target line), collide_moving.png (workload moving_boxes: steps per second per participant
   and n, grouped log bars, 60 steps/s target line), collide_refit_decay.png (moving_boxes
   per-step rows, params ...;step=K: tree quality and time against the step, one row of two
   panels per n) and collide_bv_tradeoff.png (workload triangles: exact-pairs time and build
   time against candidate pairs, one point per BVH volume type, per n).  A workload that is
   missing is reported and its figure skipped.
7. Scene pipelines (scenes suite): scenes.png, one subplot per scene, per structure a stacked
   bar of the median per-step stage times (SCENE_STAGES), the whole step as a black mark.

Validation rule: a timing row (time_per_op, build_time, time_ratio; in the collide and scenes
suites time and steps_per_second) whose `validated` column is not true is SKIPPED, because the
harness never times a wrong answer and a row that was not checked against the oracle cannot be
compared with one that was.  The number of skipped rows is
reported.  With --include-unvalidated such rows are drawn instead, with hollow markers and dashed
lines, labelled "[unvalidated]", and kept out of every other structure's fit.  Accuracy figures
(recall; the collide suite's pair counts, false-positive ratios and tree quality) are plotted
whatever their `validated` flag, since recall is itself the comparison with the oracle; the time
that goes with them follows the timing rule.

Duplicate measurements of the same point (several run_ids) are reduced to their median.
"""

import argparse
import collections
import csv
import math
import os
import re
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")  # no display; must precede pyplot
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

# --------------------------------------------------------------------------------------------
# Configuration: extend these tables, not the code below.
# --------------------------------------------------------------------------------------------

# Suites this script knows how to plot; rows of any other suite are skipped with a message.
SUITES = {
    "knn": "k-nearest, radius and approximate kNN queries on point sets",
    "radius": "ball and box range queries",
    "container": "insert / erase / find, hinted against unhinted, bulk against loop",
    "churn": "interleaved inserts and erases",
    "ray": "ray casting (first hit)",
    "collide": "all intersecting pairs: static and moving boxes, triangles per BVH volume type",
    "bv": "bounding-volume fitting and tests",
    "raycast": "first-hit ray casting against triangle meshes (ours, Embree, CGAL AABB_tree)",
    "structures": "the knn suite's static queries on every structure of the library, with the peers",
    "scenes": "scene pipelines (TOML scenes): per-step stage times",
}

# Theoretical growth of the plotted time (per operation, or total for build_time) as a function
# of n, per operation and structure.  "*" is the default structure (the trees: kd_tree, octree,
# bvh, uniform_grid and the tree-based peers); an operation not listed uses THEORY["build"] for
# build_time rows and THEORY["*"] for per-operation rows.  Names must be keys of
# COMPLEXITY_FUNCTIONS.
THEORY = {
    # operation       trees (default)        linear scans (per query: look at all n objects)
    "build":         {"*": "n log n",       "brute_force": "n"},
    "knn":           {"*": "log n",         "brute_force": "n"},
    "radius":        {"*": "log n",         "brute_force": "n"},
    "approx_knn":    {"*": "log n",         "brute_force": "n"},
    "ray":           {"*": "log n",         "brute_force": "n"},
    "find":          {"*": "log n",         "brute_force": "n"},
    "insert":        {"*": "log n",         "brute_force": "1"},
    "insert_loop":   {"*": "log n",         "brute_force": "1"},
    "insert_bulk":   {"*": "log n",         "brute_force": "1"},
    "insert_hinted": {"*": "1",             "brute_force": "1"},  # starts at the hint's leaf
    "erase":         {"*": "log n",         "brute_force": "n"},
    "erase_loop":    {"*": "log n",         "brute_force": "n"},
    "erase_bulk":    {"*": "log n",         "brute_force": "n"},
    "churn":         {"*": "log n",         "brute_force": "n"},
    "collide":       {"*": "n log n",       "brute_force": "n^2"},  # all pairs, per step
    # collide suite, boxes workload (collide_boxes.png): build + all pairs of n boxes with ~2
    # overlaps each; the grids hash each box into O(1) cells, so they are linear.
    "build_and_self_pairs": {"*": "n log n", "brute_force": "n^2", "collision_grid": "n",
                             "uniform_grid": "n", "hashed_grid": "n", "fcl_spatial_hashing": "n"},
    "fit":           {"*": "n"},
    "*":             {"*": "log n",         "brute_force": "n"},  # any other per-op query
}

COMPLEXITY_FUNCTIONS = {
    "1": lambda n: np.ones_like(n, dtype=float),
    "log n": lambda n: np.log(n),  # the base cancels once the line is anchored
    "n": lambda n: np.asarray(n, dtype=float),
    "n log n": lambda n: n * np.log(n),
    "n^2": lambda n: np.asarray(n, dtype=float) ** 2,
}

# Suites whose complexity figures are split by bounding-volume type (the `bv` column), with
# these params moved from the figure into the series label: one curve per fitting method.
SERIES_PARAMS = {"bv": ("method",)}

TIME_METRICS = {"time_per_op", "build_time", "fit_time"}
# Suites drawn only by their own figures (section "Collision and scene pipelines" below), left
# out of the generic complexity curves.
OWN_FIGURE_SUITES = ("collide", "scenes")
RATIO_METRIC = "time_ratio"
RATIO_BASELINE = "kd_tree"  # time_ratio = time(RATIO_BASELINE) / time(peer)
APPROX_OPERATION = "approx_knn"
RECALL_METRIC = "recall"

# Workloads in this order first; others (real:<file>, ...) alphabetically after them.
WORKLOAD_ORDER = ["uniform", "clusters", "sphere", "plane", "line", "lattice", "duplicates"]

UNIT_SECONDS = {"ns": 1e-9, "us": 1e-6, "\u00b5s": 1e-6, "ms": 1e-3, "s": 1.0}

METRIC_LABELS = {
    "time_per_op": "time per operation",
    "fit_time": "fit time",
    "build_time": "build time",
    "recall": "recall",
    "time_ratio": "time ratio",
}

REQUIRED_COLUMNS = ("suite", "structure", "bv", "workload", "n", "dim", "scalar", "operation",
                    "params", "metric", "value", "unit", "validated", "run_id")

SUBPLOT_INCHES = (5.0, 4.0)
DPI = 120
MAX_COLUMNS = 3
LEGEND_COLUMNS = 2

Row = collections.namedtuple("Row", REQUIRED_COLUMNS)


# --------------------------------------------------------------------------------------------
# Messages
# --------------------------------------------------------------------------------------------

def note(message):
    """A skipped input or plot: goes to stderr so stdout lists only the PNGs written."""
    print("plot_results: " + message, file=sys.stderr)


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------

def _parse_bool(text):
    return text.strip().lower() in ("true", "1", "yes")


def read_csv_file(path):
    """Rows of one results CSV; [] (with a message) if the file is unusable."""
    try:
        if os.path.getsize(path) == 0:
            note(f"skip {path}: empty file")
            return []
        with open(path, newline="", encoding="utf-8-sig") as handle:
            lines = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as error:
        note(f"skip {path}: cannot read ({error})")
        return []

    lines = [line for line in lines if any(cell.strip() for cell in line)]
    if not lines:
        note(f"skip {path}: empty file")
        return []
    header = [cell.strip() for cell in lines[0]]
    missing = [name for name in REQUIRED_COLUMNS if name not in header]
    if missing:
        note(f"skip {path}: header lacks column(s) {', '.join(missing)}")
        return []
    index = {name: header.index(name) for name in REQUIRED_COLUMNS}
    last_index = max(index.values())

    rows, bad = [], 0
    for line in lines[1:]:
        if len(line) <= last_index:
            bad += 1
            continue
        cells = {name: line[i].strip() for name, i in index.items()}
        if cells["suite"] == "suite":  # a repeated header from concatenated files
            continue
        try:
            cells["n"] = int(float(cells["n"]))
            cells["dim"] = int(float(cells["dim"]))
            cells["value"] = float(cells["value"])
        except ValueError:
            bad += 1
            continue
        if not math.isfinite(cells["value"]):
            bad += 1
            continue
        cells["validated"] = _parse_bool(cells["validated"])
        if cells["bv"] == "-":  # the collide and scenes suites write "-" for "no volume type"
            cells["bv"] = ""
        rows.append(Row(**cells))
    if bad:
        note(f"{path}: skipped {bad} malformed row(s)")
    if not rows:
        note(f"skip {path}: no data rows")
    return rows


def read_results(results_dir):
    """All usable rows of results_dir/*.csv whose suite is in SUITES."""
    if not os.path.isdir(results_dir):
        note(f"no results directory {results_dir}: nothing to plot")
        return []
    names = sorted(name for name in os.listdir(results_dir) if name.endswith(".csv"))
    if not names:
        note(f"no *.csv in {results_dir}: nothing to plot")
    rows = []
    for name in names:
        rows.extend(read_csv_file(os.path.join(results_dir, name)))
    unknown = collections.Counter(row.suite for row in rows if row.suite not in SUITES)
    for suite, count in sorted(unknown.items()):
        note(f"skip suite '{suite or '<empty>'}' ({count} rows): not in SUITES "
             f"in plots/plot_results.py")
    return [row for row in rows if row.suite in SUITES]


# --------------------------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------------------------

def fit_exponent(ns, times):
    """Least-squares slope b of log(time) = a + b log(n): time grows like n^b.

    Needs at least two distinct n and positive values; returns nan otherwise.
    """
    ns = np.asarray(ns, dtype=float)
    times = np.asarray(times, dtype=float)
    keep = (ns > 0) & (times > 0) & np.isfinite(ns) & np.isfinite(times)
    ns, times = ns[keep], times[keep]
    if len(np.unique(ns)) < 2:
        return float("nan")
    log_n, log_t = np.log(ns), np.log(times)
    design = np.column_stack([np.ones_like(log_n), log_n])
    (_, slope), *_ = np.linalg.lstsq(design, log_t, rcond=None)
    return float(slope)


def theory_for(operation, metric, structure):
    """Name of the theoretical complexity (a COMPLEXITY_FUNCTIONS key) for one series."""
    if operation in THEORY:
        entry = THEORY[operation]
    elif metric == "build_time":
        entry = THEORY["build"]
    else:
        entry = THEORY["*"]
    return entry.get(structure, entry["*"])


def parse_params(params):
    """'k=10;eps=0.5' -> [('k', '10'), ('eps', '0.5')] (order kept)."""
    pairs = []
    for item in params.split(";"):
        item = item.strip()
        if not item:
            continue
        key, _, value = item.partition("=")
        pairs.append((key.strip(), value.strip()))
    return pairs


def format_params(pairs):
    return ";".join(f"{key}={value}" if value else key for key, value in pairs)


def slug(text):
    """File-name-safe form: 'k=10;eps=0.5' -> 'k10_eps0.5', 'real:bunny.off' -> 'real-bunny.off'."""
    text = text.replace(";", "_").replace("=", "").replace(":", "-")
    text = re.sub(r"[^A-Za-z0-9._+-]+", "-", text)
    return text.strip("-_") or "none"


def format_n(n):
    exponent = math.log10(n) if n > 0 else 0.0
    if n >= 1000 and abs(exponent - round(exponent)) < 1e-12:
        return f"1e{int(round(exponent))}"
    return f"{n:,}"


def label_of(row):
    """Series label: the structure, with its bounding-volume type when there is one."""
    return f"{row.structure}<{row.bv}>" if row.bv else row.structure


def series_label(row):
    """Label of a curve: label_of(row), or for SERIES_PARAMS suites the structure and method."""
    keys = SERIES_PARAMS.get(row.suite)
    if not keys:
        return label_of(row)
    named = dict(parse_params(row.params))
    return " ".join([row.structure] + [named[key] for key in keys if key in named])


def figure_params(row):
    """The params that select a figure (SERIES_PARAMS keys removed)."""
    keys = SERIES_PARAMS.get(row.suite, ())
    return format_params([(k, v) for k, v in parse_params(row.params) if k not in keys])


def workload_sort_key(workload):
    if workload in WORKLOAD_ORDER:
        return (0, WORKLOAD_ORDER.index(workload), workload)
    return (1, 0, workload)


def common_unit(units):
    """The unit a figure is drawn in: the only one used, else seconds (None if unconvertible)."""
    units = set(units)
    if len(units) == 1:
        return units.pop()
    if all(unit in UNIT_SECONDS for unit in units):
        return "s"
    return None


def convert(value, unit, target):
    if unit == target:
        return value
    return value * UNIT_SECONDS[unit] / UNIT_SECONDS[target]


class StyleBook:
    """One colour and marker per structure label, the same in every figure."""

    MARKERS = "osD^v<>pPhX*"

    def __init__(self, labels):
        labels = sorted(set(labels))
        cmap = plt.get_cmap("tab10" if len(labels) <= 10 else "tab20")
        self.styles = {
            label: (cmap(i % cmap.N), self.MARKERS[i % len(self.MARKERS)])
            for i, label in enumerate(labels)
        }

    def __call__(self, label):
        return self.styles.get(label, ("black", "o"))


def grid_shape(count):
    columns = min(MAX_COLUMNS, count)
    rows = int(math.ceil(count / columns))
    return rows, columns


def new_figure(count, legend_entries=0, one_column=False):
    """A grid of `count` subplots; legend_entries reserves room for a legend under each.
    one_column stacks them (wide legends of many series then do not run into each other)."""
    rows, columns = (count, 1) if one_column else grid_shape(count)
    width_scale = 2.0 if one_column else 1.0
    legend_rows = math.ceil(legend_entries / LEGEND_COLUMNS)
    legend_inches = 0.2 * legend_rows + (0.3 if legend_entries else 0)
    figure, axes = plt.subplots(
        rows, columns, squeeze=False,
        figsize=(SUBPLOT_INCHES[0] * columns * width_scale, (SUBPLOT_INCHES[1] + legend_inches) * rows + 0.6))
    axes = axes.ravel()
    for extra in axes[count:]:
        extra.set_visible(False)
    return figure, axes[:count]


_UMASK = os.umask(0)
os.umask(_UMASK)


def finish_figure(figure, title):
    """Figure title above the subplots' own titles, then a tight layout under it."""
    figure.suptitle(title)
    lines = title.count("\n") + 1
    top = 1.0 - (0.5 + 0.25 * (lines - 1)) / figure.get_figheight()  # half an inch a line
    figure.tight_layout(rect=(0, 0, 1, top))


def legend_below(axis):
    """Legend under the axes, so it never hides a curve."""
    axis.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=LEGEND_COLUMNS,
                fontsize="small", frameon=False)


def save_atomically(figure, path):
    """Write the PNG to a temp file in the same directory, then rename it over `path`."""
    directory = os.path.dirname(os.path.abspath(path))
    handle, temp_path = tempfile.mkstemp(
        prefix="." + os.path.basename(path) + ".", suffix=".tmp", dir=directory)
    try:
        with os.fdopen(handle, "wb") as stream:
            figure.savefig(stream, format="png", dpi=DPI)
        os.chmod(temp_path, 0o666 & ~_UMASK)  # mkstemp makes 0600; give a normal file's mode
        os.replace(temp_path, path)
    except BaseException:
        try:
            os.unlink(temp_path)
        except OSError:
            pass
        raise
    finally:
        plt.close(figure)
    print(f"wrote {path}")
    return path


def unique_name(name, used, suffix):
    """name, or name with _suffix (then a counter) if another figure already took it."""
    if name not in used:
        return name
    stem, extension = os.path.splitext(name)
    candidate = f"{stem}_{slug(suffix)}{extension}"
    counter = 2
    while candidate in used:
        candidate = f"{stem}_{slug(suffix)}_{counter}{extension}"
        counter += 1
    return candidate


def median(values):
    return float(np.median(np.asarray(values, dtype=float)))


# --------------------------------------------------------------------------------------------
# 1. Complexity curves
# --------------------------------------------------------------------------------------------

def split_validated(rows, include_unvalidated, what):
    """Timing rows to draw, following the validation rule in the module docstring."""
    unvalidated = [row for row in rows if not row.validated]
    if unvalidated and not include_unvalidated:
        groups = sorted({(row.suite, row.operation) for row in unvalidated})
        shown = ", ".join(f"{s}/{o}" for s, o in groups[:6]) + (" ..." if len(groups) > 6 else "")
        note(f"skipped {len(unvalidated)} unvalidated {what} row(s) ({shown}); "
             f"--include-unvalidated draws them hollow")
        return [row for row in rows if row.validated]
    return rows


def fastest_series(series):
    """Label of the fastest series: lowest time at the largest n they all share."""
    shared = set.intersection(*(set(points) for points in series.values()))
    if shared:
        n = max(shared)
        return min(series, key=lambda key: series[key][n])
    # No common n: compare the geometric means.
    return min(series, key=lambda key: np.mean(np.log(list(series[key].values()))))


def plot_complexity(rows, out_dir, styles, include_unvalidated):
    # The collide and scenes suites mix totals, per-step medians and per-step series under one
    # metric name ("time"); they get their own figures (OWN_FIGURE_SUITES), not these curves.
    timing = [row for row in rows if row.metric in TIME_METRICS
              and row.suite not in OWN_FIGURE_SUITES]
    non_positive = [row for row in timing if row.value <= 0]
    if non_positive:
        note(f"skipped {len(non_positive)} timing row(s) with value <= 0 (no place on log axes)")
    timing = [row for row in timing if row.value > 0]
    timing = split_validated(timing, include_unvalidated, "timing")

    figures = collections.defaultdict(list)
    for row in timing:
        bv = row.bv if row.suite in SERIES_PARAMS else ""
        figures[(row.suite, row.operation, figure_params(row), row.dim, row.scalar, row.metric, bv)] \
            .append(row)

    # File names; an operation with two time metrics gets the metric as a suffix.
    base_names = {}
    for key in figures:
        suite, operation, params, dim, scalar, _metric, bv = key
        parts = [suite] + ([bv] if bv else []) + [operation] + ([slug(params)] if params else []) \
            + [f"{dim}d", scalar]
        base_names[key] = "_".join(slug(part) for part in parts) + ".png"
    name_counts = collections.Counter(base_names.values())

    written, used = [], set()
    for key in sorted(figures, key=lambda k: tuple(map(str, k))):
        suite, operation, params, dim, scalar, metric, bv = key
        figure_rows = figures[key]
        unit = common_unit(row.unit for row in figure_rows)
        if unit is None:
            note(f"skip {base_names[key]}: mixed units "
                 f"{sorted({row.unit for row in figure_rows})} cannot be converted")
            continue

        # workload -> (label, validated) -> n -> [values]
        panels = collections.defaultdict(
            lambda: collections.defaultdict(lambda: collections.defaultdict(list)))
        for row in figure_rows:
            series_key = (series_label(row), row.validated)
            panels[row.workload][series_key][row.n].append(convert(row.value, row.unit, unit))

        kept = []
        for workload in sorted(panels, key=workload_sort_key):
            distinct_n = {n for points in panels[workload].values() for n in points}
            if len(distinct_n) >= 2:
                kept.append(workload)
            else:
                note(f"skip {suite}/{operation} {params} {dim}d {scalar} {workload}: "
                     f"only one n ({format_n(next(iter(distinct_n)))}), no curve")
        if not kept:
            continue

        name = base_names[key]
        if name_counts[name] > 1:
            name = unique_name(name, {name}, metric)
        name = unique_name(name, used, metric)
        used.add(name)

        entries = max(len(panels[workload]) for workload in kept) + 1  # + theory line
        figure, axes = new_figure(len(kept), entries)
        for axis, workload in zip(axes, kept):
            draw_complexity_panel(axis, panels[workload], operation, metric, unit, workload, styles)
        title = f"{suite}: " + (f"{bv} " if bv else "") + operation + (f" ({params})" if params else "")
        title += f" \u2014 {METRIC_LABELS.get(metric, metric)}, {dim}D, {scalar}"
        finish_figure(figure, title)
        written.append(save_atomically(figure, os.path.join(out_dir, name)))
    return written


def draw_complexity_panel(axis, series_by_key, operation, metric, unit, workload, styles):
    series = {key: {n: median(values) for n, values in points.items()}
              for key, points in series_by_key.items()}
    order = sorted(series, key=lambda key: (key[0], not key[1]))
    for label, validated in order:
        points = series[(label, validated)]
        ns = np.array(sorted(points), dtype=float)
        times = np.array([points[n] for n in sorted(points)])
        exponent = fit_exponent(ns, times)
        text = label + ("" if validated else " [unvalidated]")
        text += f" (n^{exponent:.2f})" if math.isfinite(exponent) else " (one n)"
        colour, marker = styles(label)
        axis.plot(ns, times, marker=marker, color=colour, label=text,
                  linestyle="-" if validated else "--",
                  markerfacecolor=colour if validated else "none")

    # Theory line: anchored at the smallest-n point of the fastest series, chosen among the
    # validated ones and, of those, the ones the default ("*", tree) theory applies to, so that
    # a trivially fast linear-scan build does not replace the n log n line by an n line.
    candidates = {key: points for key, points in series.items() if key[1]} or series
    default = theory_for(operation, metric, "*")
    trees = {key: points for key, points in candidates.items()
             if theory_for(operation, metric, key[0].split("<")[0]) == default}
    fastest = fastest_series(trees or candidates)
    candidates = trees or candidates
    anchor_n = min(candidates[fastest])
    anchor_t = candidates[fastest][anchor_n]
    structure = fastest[0].split("<")[0]
    complexity = theory_for(operation, metric, structure)
    function = COMPLEXITY_FUNCTIONS.get(complexity)
    all_n = sorted({n for points in series.values() for n in points if n >= anchor_n})
    if function is not None and len(all_n) >= 2:
        ns = np.array(all_n, dtype=float)
        base = float(function(np.array([float(anchor_n)]))[0])
        if base > 0 and math.isfinite(base):
            axis.plot(ns, anchor_t * function(ns) / base, color="grey", linestyle="--",
                      linewidth=1.2, label=f"theory O({complexity})", zorder=1)

    axis.set_xscale("log")
    axis.set_yscale("log")
    axis.set_title(workload)
    axis.set_xlabel("n (objects)")
    axis.set_ylabel(f"{METRIC_LABELS.get(metric, metric)} ({unit})")
    axis.grid(True, which="major", alpha=0.5)
    axis.grid(True, which="minor", alpha=0.15)
    legend_below(axis)


# --------------------------------------------------------------------------------------------
# 2. Accuracy against time (approximate kNN)
# --------------------------------------------------------------------------------------------

def plot_recall_vs_time(rows, out_dir, styles, include_unvalidated):
    approx = [row for row in rows if row.operation == APPROX_OPERATION
              and any(key == "eps" for key, _ in parse_params(row.params))]
    times = [row for row in approx if row.metric == "time_per_op" and row.value > 0]
    times = split_validated(times, include_unvalidated, f"{APPROX_OPERATION} timing")
    recalls = [row for row in approx if row.metric == RECALL_METRIC]
    if not times or not recalls:
        if approx:
            note(f"skip recall-vs-time plots: {APPROX_OPERATION} rows lack "
                 f"{'time_per_op' if not times else RECALL_METRIC}")
        return []

    def point_key(row):
        return (row.suite, row.workload, row.dim, row.scalar, row.n, label_of(row), row.params)

    time_values = collections.defaultdict(list)
    time_units = collections.defaultdict(set)
    for row in times:
        time_values[point_key(row)].append(row)
    recall_values = collections.defaultdict(list)
    for row in recalls:
        recall_values[point_key(row)].append(row.value)

    # figure (suite, workload, dim, scalar) -> n
    #   -> [(label, other params, eps value, eps text, time rows, recall)]
    figures = collections.defaultdict(lambda: collections.defaultdict(list))
    for key, time_rows in time_values.items():
        if key not in recall_values:
            continue
        suite, workload, dim, scalar, n, label, params = key
        pairs = parse_params(params)
        eps = dict(pairs)["eps"]
        try:
            eps_value = float(eps)
        except ValueError:
            continue
        others = format_params([(k, v) for k, v in pairs if k != "eps"])
        figures[(suite, workload, dim, scalar)][n].append(
            (label, others, eps_value, eps, time_rows, median(recall_values[key])))
        time_units[(suite, workload, dim, scalar)].update(row.unit for row in time_rows)

    written = []
    for key in sorted(figures, key=lambda k: (k[0], workload_sort_key(k[1]), k[2], k[3])):
        suite, workload, dim, scalar = key
        n = max(figures[key])
        unit = common_unit(time_units[key])
        if unit is None:
            note(f"skip recall vs time {suite} {workload}: mixed time units")
            continue
        curves = collections.defaultdict(list)
        for label, others, eps_value, eps, time_rows, recall in figures[key][n]:
            time = median([convert(row.value, row.unit, unit) for row in time_rows])
            validated = all(row.validated for row in time_rows)
            curves[(label, others, validated)].append((eps_value, eps, time, recall))
        several_others = len({others for _, others, _ in curves}) > 1

        figure, (axis,) = new_figure(1)
        for (label, others, validated) in sorted(curves, key=lambda k: (k[0], k[1], not k[2])):
            points = sorted(curves[(label, others, validated)])
            colour, marker = styles(label)
            text = label + (f" {others}" if several_others and others else "")
            text += "" if validated else " [unvalidated]"
            axis.plot([p[2] for p in points], [p[3] for p in points], marker=marker,
                      color=colour, label=text, linestyle="-" if validated else "--",
                      markerfacecolor=colour if validated else "none")
            for _, eps, time, recall in points:
                axis.annotate(eps, (time, recall), textcoords="offset points",
                              xytext=(4, -9), fontsize=7, color=colour)
        axis.set_xscale("log")
        low = min(min(p[3] for p in points) for points in curves.values())
        axis.set_ylim(min(0.0, low) - 0.02, 1.05)
        axis.set_xlabel(f"time per query ({unit})")
        axis.set_ylabel("recall (ratio)")
        others_all = {others for _, others, _ in curves}
        shared = f" ({others_all.pop()})" if len(others_all) == 1 and "" not in others_all else ""
        axis.set_title(f"{suite}: approximate kNN{shared}, recall vs time\n"
                       f"{workload}, n={format_n(n)}, {dim}D, {scalar}")
        axis.grid(True, which="major", alpha=0.5)
        axis.grid(True, which="minor", alpha=0.15)
        # Lower right stays empty on a recall/time front (slow answers are accurate ones).
        axis.legend(fontsize="small", loc="lower right", title="point labels: eps",
                    title_fontsize="small")
        figure.tight_layout()
        name = f"{slug(suite)}_recall_vs_time_{slug(workload)}_{dim}d_{slug(scalar)}.png"
        written.append(save_atomically(figure, os.path.join(out_dir, name)))
    return written


# --------------------------------------------------------------------------------------------
# 3. Ratios
# --------------------------------------------------------------------------------------------

def plot_ratios(rows, out_dir, styles, include_unvalidated):
    """Bars of time(RATIO_BASELINE) / time(peer), one subplot per (workload, dim, scalar).

    A time_ratio row names the peer in `structure`, or in a `vs=` / `peer=` param (then
    `structure` is the baseline); `vs`/`peer` is dropped from the (operation, params) group.
    Each peer is shown at the largest n it was measured at (brute force often stops early);
    the legend says so when that n is below the subplot's largest.
    """
    ratio_rows = [row for row in rows if row.metric == RATIO_METRIC and row.value > 0]
    ratio_rows = split_validated(ratio_rows, include_unvalidated, RATIO_METRIC)
    written = []
    for suite in sorted({row.suite for row in ratio_rows}):
        # panel (workload, dim, scalar) -> peer -> (operation, params) -> n -> [values]
        panels = collections.defaultdict(lambda: collections.defaultdict(
            lambda: collections.defaultdict(lambda: collections.defaultdict(list))))
        for row in ratio_rows:
            if row.suite != suite:
                continue
            pairs = parse_params(row.params)
            named = dict(pairs)
            peer = named.get("vs") or named.get("peer") or label_of(row)
            params = format_params([(k, v) for k, v in pairs if k not in ("vs", "peer")])
            if not row.validated:
                peer += " [unvalidated]"
            panels[(row.workload, row.dim, row.scalar)][peer][(row.operation, params)][row.n] \
                .append(row.value)

        keys = sorted(panels, key=lambda k: (workload_sort_key(k[0]), k[1], k[2]))
        entries = max(len(panels[key]) for key in keys) + 1  # + the 1.0 line
        figure, axes = new_figure(len(keys), entries)
        for axis, key in zip(axes, keys):
            draw_ratio_panel(axis, key, panels[key], styles)
        finish_figure(figure, f"{suite}: {RATIO_BASELINE} time / peer time "
                              f"(below 1: {RATIO_BASELINE} faster)")
        written.append(save_atomically(figure, os.path.join(out_dir, f"{slug(suite)}_ratios.png")))
    return written


def draw_ratio_panel(axis, key, by_peer, styles):
    workload, dim, scalar = key
    peers = sorted(by_peer)
    peer_n = {peer: max(n for group in by_peer[peer].values() for n in group) for peer in peers}
    largest_n = max(peer_n.values())
    group_keys = sorted({group for peer in peers for group in by_peer[peer]})
    width = 0.8 / len(peers)
    positions = np.arange(len(group_keys))
    heights_seen = []
    for i, peer in enumerate(peers):
        n = peer_n[peer]
        heights = [median(by_peer[peer][group][n]) if n in by_peer[peer].get(group, {})
                   else np.nan for group in group_keys]
        heights_seen += [h for h in heights if math.isfinite(h)]
        colour, _ = styles(peer.split(" [")[0])
        unvalidated = peer.endswith("[unvalidated]")
        label = peer + (f" (n={format_n(n)})" if n != largest_n else "")
        bars = axis.bar(positions + (i - (len(peers) - 1) / 2) * width, heights, width,
                        label=label, color=colour, edgecolor=colour,
                        fill=not unvalidated, hatch="//" if unvalidated else None)
        axis.bar_label(bars, fmt="%.3g", fontsize=6, padding=1)
    axis.axhline(1.0, color="grey", linestyle="--", linewidth=1.0, label="equal time (1.0)")
    if heights_seen and max(heights_seen) / min(heights_seen) > 10:
        axis.set_yscale("log")  # ratios spanning decades (brute force) hide each other linearly
    else:
        axis.set_ylim(0, max(heights_seen + [1.0]) * 1.12)  # room for the value labels
    axis.set_xticks(positions)
    axis.set_xticklabels([f"{op}\n{params}" if params else op for op, params in group_keys],
                         fontsize="small")
    axis.set_ylabel(f"{RATIO_BASELINE} time / peer time (ratio)")
    axis.set_title(f"{workload}, n={format_n(largest_n)}, {dim}D, {scalar}")
    axis.grid(True, axis="y", alpha=0.5)
    legend_below(axis)


# --------------------------------------------------------------------------------------------
# 4. Bounding volumes: accuracy against time, with the Pareto front
# --------------------------------------------------------------------------------------------

BV_TRADEOFF_FILE = "bv_tradeoff.png"
BV_REFERENCE_N = 100000  # fit figures are compared at this n (else the largest n measured)


def geometric_mean(values):
    values = [v for v in values if v > 0 and math.isfinite(v)]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else float("nan")


def pareto_front(points):
    """Indices of the points not dominated in (x, y), both to be minimised, sorted by x."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best_y = [], float("inf")
    for i in order:
        if points[i][1] < best_y:
            front.append(i)
            best_y = points[i][1]
    return front


def arithmetic_mean(values):
    values = [v for v in values if math.isfinite(v)]
    return sum(values) / len(values) if values else float("nan")


def bv_points(rows, operation, x_metric, y_metric, n_choice, group_params=("method",),
              y_mean=geometric_mean):
    """(label, x, y) per (structure, bv, method[, test]): the geometric mean over workloads of
    the median x, and y_mean (geometric by default; arithmetic for rates, which may be 0) of
    the median y, at one n per workload (n_choice picks it from the ns measured)."""
    cells = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in rows:
        if row.operation != operation or row.metric not in (x_metric, y_metric):
            continue
        named = dict(parse_params(row.params))
        key = (row.structure, row.bv) + tuple(named.get(k, "") for k in group_params)
        cells[(key, row.workload, row.n)][row.metric].append(row.value)
    by_key = collections.defaultdict(dict)  # key -> workload -> n -> (x, y)
    for (key, workload, n), metrics in cells.items():
        if x_metric in metrics and y_metric in metrics:
            by_key[key].setdefault(workload, {})[n] = (median(metrics[x_metric]),
                                                       median(metrics[y_metric]))
    points = []
    for key, workloads in sorted(by_key.items()):
        xs, ys = [], []
        for per_n in workloads.values():
            n = n_choice(sorted(per_n))
            xs.append(per_n[n][0])
            ys.append(per_n[n][1])
        structure, bv, *rest = key
        label = f"{bv} {' '.join(r for r in rest if r)}" + ("" if structure == "spatialbench"
                                                             else f" [{structure}]")
        points.append((label, geometric_mean(xs), y_mean(ys)))
    return [p for p in points if math.isfinite(p[1]) and math.isfinite(p[2])]


def draw_tradeoff_panel(axis, points, xlabel, ylabel, title, log_y=True):
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


def plot_bv_tradeoff(rows, out_dir, include_unvalidated):
    """plots/bv_tradeoff.png: tightness (volume / convex hull volume) against fit time, and
    the false-positive rate of the overlap test (pairs whose enclosed shapes are disjoint but
    whose volumes overlap) and tightness against the overlap-test time; one point per type x
    method (x test), geometric means over the shapes, the Pareto front marked."""
    bv_rows = [row for row in rows if row.suite == "bv"]
    if not bv_rows:
        return []
    bv_rows = [row for row in bv_rows if row.validated or include_unvalidated]

    def at_reference_n(ns):
        return BV_REFERENCE_N if BV_REFERENCE_N in ns else max(ns)

    fit = bv_points(bv_rows, "fit", "fit_time", "tightness", at_reference_n)
    overlap = bv_points(bv_rows, "overlap", "time_per_op", "false_positive_rate_shapes", max,
                        ("method", "test"), y_mean=arithmetic_mean)
    tight_by_method = {label.split(" [")[0]: y for label, _, y in fit}
    overlap_tight = []
    for label, x, _ in overlap:
        parts = label.split(" ")
        key = " ".join(parts[:2])  # "<bv> <method>"
        if key in tight_by_method:
            overlap_tight.append((label, x, tight_by_method[key]))
    panels = [p for p in (fit, overlap_tight, overlap) if p]
    if not panels:
        note("skip bv_tradeoff.png: no fit/overlap rows with both time and accuracy")
        return []
    figure, axes = plt.subplots(1, 3, figsize=(19, 6.5), squeeze=False)
    axes = axes[0]
    if fit:
        draw_tradeoff_panel(axes[0], fit, "fit time (s), n = 1e5 where measured",
                            "tightness: volume / convex hull volume",
                            "tightness against fit time")
    if overlap_tight:
        draw_tradeoff_panel(axes[1], overlap_tight, "overlap test time (ns)",
                            "tightness: volume / convex hull volume",
                            "tightness against overlap-test time")
    if overlap:
        y = [(label, x, max(v, 1e-4)) for label, x, v in overlap]
        draw_tradeoff_panel(axes[2], y, "overlap test time (ns)",
                            "false-positive rate vs. the enclosed shapes\n(mean over shapes; 0 drawn at 1e-4)",
                            "pruning power against overlap-test time")
    figure.suptitle("bv: accuracy against time (times and tightness: geometric means over "
                    "shapes; lower-left is better; stars = Pareto front)")
    figure.tight_layout()
    return [save_atomically(figure, os.path.join(out_dir, BV_TRADEOFF_FILE))]


# --------------------------------------------------------------------------------------------
# Entry point
# --------------------------------------------------------------------------------------------

# --------------------------------------------------------------------------------------------
# Ray casting: time per ray against n, all structures and workloads in one figure
# --------------------------------------------------------------------------------------------

RAYCAST_SUITE = "raycast"
RAYCAST_FILE = "raycast_time_per_ray.png"
RAYCAST_LINESTYLES = {"sphere": "-", "soup": "--"}  # other generated workloads: dotted
REAL_PREFIX = "real:"


def raycast_series(rows, include_unvalidated=False):
    """{params: {(structure label, workload, validated): {n: median time}}}, and the unit.

    From the raycast suite's operation=ray, metric=time_per_op rows, following the validation
    rule (unvalidated rows dropped unless include_unvalidated)."""
    timing = [row for row in rows if row.suite == RAYCAST_SUITE and row.operation == "ray"
              and row.metric == "time_per_op" and row.value > 0]
    timing = split_validated(timing, include_unvalidated, "raycast timing")
    unit = common_unit(row.unit for row in timing) if timing else None
    if unit is None:
        return {}, None
    raw = collections.defaultdict(lambda: collections.defaultdict(lambda: collections.defaultdict(list)))
    for row in timing:
        raw[row.params][(label_of(row), row.workload, row.validated)][row.n].append(
            convert(row.value, row.unit, unit))
    series = {params: {key: {n: median(values) for n, values in points.items()}
                       for key, points in by_key.items()}
              for params, by_key in raw.items()}
    return series, unit


def plot_raycast(rows, out_dir, styles, include_unvalidated):
    series, unit = raycast_series(rows, include_unvalidated)
    if not series:
        return []
    panels = sorted(series)
    entries = max(len({(label, workload) for label, workload, _ in by_key}) for by_key in series.values())
    figure, axes = new_figure(len(panels), entries, one_column=True)
    for axis, params in zip(axes, panels):
        real_labelled = set()
        for (label, workload, validated), points in sorted(series[params].items(),
                                                           key=lambda item: tuple(map(str, item[0]))):
            colour, marker = styles(label)
            ns = sorted(points)
            times = [points[n] for n in ns]
            suffix = "" if validated else " [unvalidated]"
            if workload.startswith(REAL_PREFIX):
                text = f"{label} real meshes{suffix}" if (label, validated) not in real_labelled else None
                real_labelled.add((label, validated))
                axis.plot(ns, times, linestyle="none", marker="x", color=colour, label=text)
                continue
            exponent = fit_exponent(ns, times)
            text = f"{label} {workload}{suffix}"
            text += f" (n^{exponent:.2f})" if math.isfinite(exponent) else ""
            axis.plot(ns, times, marker=marker, color=colour, label=text,
                      linestyle=RAYCAST_LINESTYLES.get(workload, ":"),
                      markerfacecolor=colour if validated else "none")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_title(params or "rays")
        axis.set_xlabel("n (triangles)")
        axis.set_ylabel(f"time per ray ({unit})")
        axis.grid(True, which="major", alpha=0.5)
        axis.grid(True, which="minor", alpha=0.15)
        legend_below(axis)
    finish_figure(figure, "raycast: time per ray against mesh size (median of repetitions)")
    return [save_atomically(figure, os.path.join(out_dir, RAYCAST_FILE))]


# --------------------------------------------------------------------------------------------
# Accuracy costs time, for the BVH: node tightness per BV type against build and ray time,
# and the median builder against SAH
# --------------------------------------------------------------------------------------------

BVH_TRADEOFF_FILE = "bvh_tradeoff.png"
BVH_BUILDERS = {"bvh": "SAH", "bvh_median": "median"}


def bvh_tradeoff_points(rows, include_unvalidated):
    """{workload: {"n": n, "points": [(bv, area_ratio, build_s, ray_ns)], "builders": [(label, n,
    build_s, ray_ns)]}} from the raycast suite: per workload the n at which the most bvh_*
    structures have a tightness row (the largest such n); incoherent rays."""
    raycast = [row for row in rows if row.suite == RAYCAST_SUITE and row.structure.startswith("bvh")]
    raycast = [row for row in raycast if row.validated or include_unvalidated
               or row.metric not in TIME_METRICS]
    value = {}
    for row in raycast:
        if row.operation == "build" and row.metric in ("build_time", "node_area_ratio"):
            value[(row.structure, row.bv, row.workload, row.n, row.metric)] = row.value
        elif (row.operation == "ray" and row.metric == "time_per_op"
              and dict(parse_params(row.params)).get("rays") == "incoherent"):
            value[(row.structure, row.bv, row.workload, row.n, "ray")] = convert(row.value, row.unit, "ns")
    out = {}
    for workload in sorted({key[2] for key in value}, key=workload_sort_key):
        tight_ns = [key[3] for key in value if key[2] == workload and key[4] == "node_area_ratio"]
        entry = {"n": None, "points": [], "builders": []}
        if tight_ns:
            # The n with the most volume types (runs restricted to a few structures at a
            # larger n add single points), the largest such n.
            n = max(set(tight_ns), key=lambda m: (tight_ns.count(m), m))
            entry["n"] = n
            for (structure, bv, w, m, metric), ratio in sorted(value.items()):
                if w != workload or m != n or metric != "node_area_ratio" or structure == "bvh_median":
                    continue
                build = value.get((structure, bv, w, m, "build_time"))
                ray = value.get((structure, bv, w, m, "ray"))
                if build and ray:
                    entry["points"].append((bv or structure, ratio, build, ray))
        for (structure, bv, w, m, metric), build in sorted(value.items()):
            if w == workload and metric == "build_time" and structure in BVH_BUILDERS:
                ray = value.get((structure, bv, w, m, "ray"))
                if ray:
                    entry["builders"].append((BVH_BUILDERS[structure], m, build, ray))
        if entry["points"] or entry["builders"]:
            out[workload] = entry
    return out


def plot_bvh_tradeoff(rows, out_dir, include_unvalidated):
    """plots/bvh_tradeoff.png, per workload (one row each): node tightness (sum over nodes of
    the volume's surface area / the node AABB's; 1 = aabb, lower = tighter) against build time
    and against time per incoherent ray, one point per BV type at the largest n; and the median
    builder against SAH, build time against ray time at every n."""
    data = bvh_tradeoff_points(rows, include_unvalidated)
    if not data:
        return []
    figure, axes = plt.subplots(len(data), 3, figsize=(19, 6 * len(data)), squeeze=False)
    for row_axes, (workload, entry) in zip(axes, data.items()):
        points = entry["points"]
        if not points:
            for axis in row_axes[:2]:
                axis.set_axis_off()
                axis.text(0.5, 0.5, f"{workload}: no node-tightness rows", ha="center", va="center")
        if points:
            n_text = format_n(entry["n"])
            draw_tradeoff_panel(row_axes[0], [(label, b, r) for label, r, b, _ in points],
                                "build time (s)", "node tightness: sum area(BV) / sum area(AABB)",
                                f"{workload} n={n_text}: tightness against build time", log_y=False)
            draw_tradeoff_panel(row_axes[1], [(label, t, r) for label, r, _, t in points],
                                "time per incoherent ray (ns)",
                                "node tightness: sum area(BV) / sum area(AABB)",
                                f"{workload} n={n_text}: tightness against ray time", log_y=False)
        axis = row_axes[2]
        for builder, marker in (("SAH", "o"), ("median", "s")):
            pts = sorted((n, b, r) for label, n, b, r in entry["builders"] if label == builder)
            if not pts:
                continue
            axis.plot([b for _, b, _ in pts], [r for _, _, r in pts], marker=marker, label=builder)
            for n, b, r in pts:
                axis.annotate(format_n(n), (b, r), fontsize=7, xytext=(3, 3), textcoords="offset points")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("build time (s)")
        axis.set_ylabel("time per incoherent ray (ns)")
        axis.set_title(f"{workload}: median split against binned SAH (aabb; labels: n)", fontsize="medium")
        axis.grid(True, which="both", alpha=0.3)
        if entry["builders"]:
            axis.legend(fontsize="small")
    figure.suptitle("bvh: what node tightness and the builder cost (raycast suite; lower-left is better)")
    figure.tight_layout(rect=(0, 0, 1, 0.985))
    return [save_atomically(figure, os.path.join(out_dir, BVH_TRADEOFF_FILE))]


# --------------------------------------------------------------------------------------------
# Collision (collide suite) and scene pipelines (scenes suite)
# --------------------------------------------------------------------------------------------

COLLIDE_SUITE = "collide"
SCENES_SUITE = "scenes"
COLLIDE_BOXES_FILE = "collide_boxes.png"
COLLIDE_MOVING_FILE = "collide_moving.png"
COLLIDE_DECAY_FILE = "collide_refit_decay.png"
COLLIDE_BV_FILE = "collide_bv_tradeoff.png"
SCENES_FILE = "scenes.png"
COLLIDE_TIME = "time"  # these suites' time metric (median seconds; per step where stepped)
COLLIDE_STEPS_PER_SECOND = "steps_per_second"
COLLIDE_BASELINE = "cgal_box_intersection"  # speed-up = time(baseline) / time(participant)
COLLIDE_SPEEDUP_TARGET = (5.0, "collision_grid", 1000000)  # the issue: >= 5x CGAL at 1e6
COLLIDE_STEPS_TARGET = (60.0, 100000)  # the issue: >= 60 steps/s (update + pairs) at 1e5
STEP_PARAM = "step"  # params key of the per-step rows of moving_boxes
# Per-step stages of a scene, stacked bottom-up in this order; other operations with a time
# row (except SCENE_SKIP) are stacked after them.  SCENE_TOTAL is their sum, drawn as a mark.
SCENE_STAGES = ("motion", "churn", "update", "collide_broad_phase", "collide_narrow_phase",
                "raycast", "nearest", "range")
SCENE_TOTAL = "step"
SCENE_SKIP = ("build",)  # once per scene, not per step
SCENE_UNIT = "ms"


def without_params(params, keys):
    """params with the given keys removed: ('a=1;step=3', ('step',)) -> 'a=1'."""
    return format_params([(k, v) for k, v in parse_params(params) if k not in keys])


def collide_timing(rows, include_unvalidated, what, **selection):
    """Rows of the collide/scenes suites matching selection (field=value; a tuple value means
    any of), positive, following the validation rule."""
    picked = [row for row in rows
              if all(getattr(row, field) in value if isinstance(value, tuple)
                     else getattr(row, field) == value for field, value in selection.items())
              and row.value > 0]
    return split_validated(picked, include_unvalidated, what)


def median_points(series):
    """{key: {x: [values]}} -> {key: {x: median}}."""
    return {key: {x: median(values) for x, values in points.items()}
            for key, points in series.items()}


def validated_first(item):
    """Sort key of ((label, validated), points) items: by label, validated before not."""
    (label, validated), _ = item
    return (label, not validated)


def speedups(series, baseline=COLLIDE_BASELINE):
    """{(label, validated): {n: time(baseline) / time(label)}} at every n both were measured.

    series: {(label, validated): {n: time}}; the baseline is the series whose structure (label
    without <bv>) is `baseline`, its validated series preferred.  The baseline itself is left
    out; {} without a baseline."""
    keys = [key for key in series if key[0].split("<")[0] == baseline]
    if not keys:
        return {}
    base = series[max(keys, key=lambda key: key[1])]
    out = {}
    for key, points in series.items():
        if key in keys:
            continue
        ratios = {n: base[n] / time for n, time in points.items() if n in base and time > 0}
        if ratios:
            out[key] = ratios
    return out


def collide_boxes_series(rows, include_unvalidated):
    """{(params, dim, scalar): {(label, validated): {n: [time (s)]}}} of the static boxes
    workload, operation build_and_self_pairs (build + all pairs)."""
    timing = collide_timing(rows, include_unvalidated, "collide boxes timing", suite=COLLIDE_SUITE,
                            workload="boxes", operation="build_and_self_pairs", metric=COLLIDE_TIME)
    out = collections.defaultdict(lambda: collections.defaultdict(lambda: collections.defaultdict(list)))
    for row in timing:
        if row.unit not in UNIT_SECONDS:
            continue
        out[(row.params, row.dim, row.scalar)][(label_of(row), row.validated)][row.n].append(
            convert(row.value, row.unit, "s"))
    return out


def emphasise(axis, structure):
    """Thicker lines for the series of `structure` (the one a target is about)."""
    for line in axis.get_lines():
        if line.get_label().split("<")[0].split(" ")[0] == structure:
            line.set_linewidth(2.5)
            line.set_zorder(4)


def plot_collide_boxes(rows, out_dir, styles, include_unvalidated):
    data = collide_boxes_series(rows, include_unvalidated)
    if not data:
        note(f"skip {COLLIDE_BOXES_FILE}: no collide rows of workload boxes, "
             f"operation build_and_self_pairs, metric time")
        return []
    configs = sorted(data, key=lambda k: tuple(map(str, k)))
    entries = max(len(series) for series in data.values()) + 2
    legend_inches = 0.2 * math.ceil(entries / LEGEND_COLUMNS) + 0.3
    figure, axes = plt.subplots(len(configs), 2, squeeze=False,
                                figsize=(13, (4.6 + legend_inches) * len(configs) + 0.6))
    target, target_structure, target_n = COLLIDE_SPEEDUP_TARGET
    for (left, right), config in zip(axes, configs):
        params, dim, scalar = config
        series = data[config]
        where = f"boxes ({params}), {dim}D, {scalar}" if params else f"boxes, {dim}D, {scalar}"
        draw_complexity_panel(left, series, "build_and_self_pairs", COLLIDE_TIME, "s", where, styles)
        left.set_xlabel("n (boxes)")
        left.set_ylabel("build + all pairs time (s)")
        left.set_title(f"{where}\nbuild + self pairs, legend: fitted exponent", fontsize="medium")
        emphasise(left, target_structure)
        legend_below(left)

        ratios = speedups(median_points(series))
        if not ratios:
            note(f"{COLLIDE_BOXES_FILE}: no {COLLIDE_BASELINE} rows for {where}, no speed-up panel")
            right.set_axis_off()
            right.text(0.5, 0.5, f"no {COLLIDE_BASELINE} rows:\nno speed-up", ha="center",
                       va="center")
            continue
        for (label, validated), points in sorted(ratios.items(), key=validated_first):
            ns = sorted(points)
            colour, marker = styles(label)
            right.plot(ns, [points[n] for n in ns], marker=marker, color=colour,
                       linestyle="-" if validated else "--",
                       markerfacecolor=colour if validated else "none",
                       label=label + ("" if validated else " [unvalidated]"))
            if label.split("<")[0] == target_structure:
                for n in ns:
                    right.annotate(f"{points[n]:.3g}x", (n, points[n]), fontsize=7, color=colour,
                                   xytext=(0, 6), textcoords="offset points", ha="center")
        right.axhline(1.0, color="grey", linestyle=":", linewidth=1.0,
                      label=f"{COLLIDE_BASELINE} (1x)")
        right.axhline(target, color="red", linestyle="--", linewidth=1.0,
                      label=f"target: {target_structure} \u2265 {target:g}x at n={format_n(target_n)}")
        right.set_xscale("log")
        right.set_yscale("log")
        right.margins(x=0.08, y=0.12)
        emphasise(right, target_structure)
        right.set_xlabel("n (boxes)")
        right.set_ylabel(f"speed-up: {COLLIDE_BASELINE} time / time (ratio)")
        right.set_title(f"{where}\nspeed-up over {COLLIDE_BASELINE} (above 1: faster)",
                        fontsize="medium")
        right.grid(True, which="major", alpha=0.5)
        right.grid(True, which="minor", alpha=0.15)
        legend_below(right)
    finish_figure(figure, "collide: static self-intersection of n random boxes "
                          "(build + all pairs, median of repetitions)")
    return [save_atomically(figure, os.path.join(out_dir, COLLIDE_BOXES_FILE))]


def collide_moving_bars(rows, include_unvalidated):
    """Steps per second of moving_boxes (operation update_and_self_pairs, the rows without a
    step= param): (groups [(n, params)] in order, {(label, validated): {group: median}},
    {group: median pairs changed per step})."""
    moving = [row for row in rows if row.suite == COLLIDE_SUITE and row.workload == "moving_boxes"
              and row.operation == "update_and_self_pairs"
              and STEP_PARAM not in dict(parse_params(row.params))]
    rates = collide_timing(moving, include_unvalidated, "collide moving_boxes steps/s",
                           metric=COLLIDE_STEPS_PER_SECOND)
    values = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in rates:
        values[(label_of(row), row.validated)][(row.n, row.params)].append(row.value)
    changed = collections.defaultdict(list)
    for row in moving:
        if row.metric == "pairs_changed_per_step":
            changed[(row.n, row.params)].append(row.value)
    groups = sorted({group for points in values.values() for group in points})
    return groups, median_points(values), {g: median(v) for g, v in changed.items()}


def plot_collide_moving(rows, out_dir, styles, include_unvalidated):
    groups, bars, changed = collide_moving_bars(rows, include_unvalidated)
    if not groups:
        note(f"skip {COLLIDE_MOVING_FILE}: no collide rows of workload moving_boxes with "
             f"metric {COLLIDE_STEPS_PER_SECOND}")
        return []
    several_params = len({params for _, params in groups}) > 1
    participants = sorted(bars, key=lambda key: (key[0], not key[1]))
    # Each group packs only the participants measured at its n (peers may stop early), so
    # every group is as wide as the widest one and the bars of a group are adjacent.
    present = {group: [key for key in participants if group in bars[key]] for group in groups}
    widest = max(len(keys) for keys in present.values())
    width = 0.85 / widest
    positions = np.arange(len(groups))
    figure, axis = plt.subplots(figsize=(max(9.0, 1.5 + 0.32 * sum(map(len, present.values()))), 7.5))
    for key in participants:
        label, validated = key
        xs, heights = [], []
        for g, group in enumerate(groups):
            if group in bars[key]:
                i = present[group].index(key)
                xs.append(positions[g] + (i - (len(present[group]) - 1) / 2) * width)
                heights.append(bars[key][group])
        colour, _ = styles(label)
        drawn = axis.bar(xs, heights, width, color=colour, edgecolor=colour, fill=validated,
                         hatch=None if validated else "//",
                         label=label + ("" if validated else " [unvalidated]"))
        axis.bar_label(drawn, labels=[f"{h:.3g}" for h in heights], fontsize=6, padding=1,
                       rotation=90)
    target, target_n = COLLIDE_STEPS_TARGET
    axis.axhline(target, color="red", linestyle="--", linewidth=1.0,
                 label=f"target: {target:g} steps/s at n={format_n(target_n)}")
    ticks = []
    for n, params in groups:
        text = f"n={format_n(n)}"
        if several_params:
            text += "\n" + without_params(params, ("overlaps_per_box",))
        if (n, params) in changed:
            text += f"\n{changed[(n, params)]:,.0f} pairs changed/step"
        ticks.append(text)
    axis.set_xticks(positions)
    axis.set_xticklabels(ticks, fontsize="small")
    axis.set_yscale("log")
    low, high = axis.get_ylim()
    axis.set_ylim(low, high * 3)  # room for the value labels
    axis.set_ylabel("steps per second (1 / median step time; update + all pairs)")
    shared = "" if several_params else f" ({groups[0][1]})"
    axis.set_title(f"moving_boxes{shared}: one step = move every box, update the structure, "
                   f"report all overlapping pairs", fontsize="medium")
    axis.grid(True, axis="y", which="both", alpha=0.3)
    axis.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=4, fontsize="small",
                frameon=False)
    finish_figure(figure, "collide: steps per second on moving boxes (higher is better)")
    return [save_atomically(figure, os.path.join(out_dir, COLLIDE_MOVING_FILE))]


def refit_decay_series(rows, include_unvalidated):
    """{(n, params without step): {metric: {(label, validated): {step: median}}}} of the
    moving_boxes per-step rows (params with step=K), metrics quality and time.  Quality is a
    property of the tree, not a timing: it is drawn whatever its validated flag."""
    stepped = [row for row in rows if row.suite == COLLIDE_SUITE and row.workload == "moving_boxes"
               and STEP_PARAM in dict(parse_params(row.params))]
    timing = collide_timing(stepped, include_unvalidated, "collide per-step timing",
                            metric=COLLIDE_TIME)
    quality = [row for row in stepped if row.metric == "quality"]
    out = collections.defaultdict(lambda: collections.defaultdict(
        lambda: collections.defaultdict(lambda: collections.defaultdict(list))))
    for row in timing + quality:
        try:
            step = int(float(dict(parse_params(row.params))[STEP_PARAM]))
        except ValueError:
            continue
        if row.metric == COLLIDE_TIME and row.unit not in UNIT_SECONDS:
            continue
        value = convert(row.value, row.unit, "ms") if row.metric == COLLIDE_TIME else row.value
        out[(row.n, without_params(row.params, (STEP_PARAM,)))][row.metric][
            (label_of(row), row.validated)][step].append(value)
    return {group: {metric: median_points(series) for metric, series in metrics.items()}
            for group, metrics in out.items()}


def plot_collide_refit_decay(rows, out_dir, styles, include_unvalidated):
    data = refit_decay_series(rows, include_unvalidated)
    if not data:
        note(f"skip {COLLIDE_DECAY_FILE}: no per-step ({STEP_PARAM}=K) collide rows of "
             f"workload moving_boxes")
        return []
    groups = sorted(data)
    entries = max(len(series) for metrics in data.values() for series in metrics.values())
    legend_inches = 0.2 * math.ceil(entries / LEGEND_COLUMNS) + 0.3
    figure, axes = plt.subplots(len(groups), 2, squeeze=False,
                                figsize=(13, (4.2 + legend_inches) * len(groups) + 0.6))
    panels = (("quality", "quality: SAH node-area sum / root area (ratio)", "tree quality"),
              (COLLIDE_TIME, "update + all pairs time (ms)", "time per step"))
    for row_axes, group in zip(axes, groups):
        n, params = group
        for axis, (metric, ylabel, what) in zip(row_axes, panels):
            series = data[group].get(metric, {})
            title = f"n={format_n(n)} ({params}): {what}" if params else f"n={format_n(n)}: {what}"
            if not series:
                axis.set_axis_off()
                axis.text(0.5, 0.5, f"{title}\nno {metric} rows", ha="center", va="center")
                continue
            values = []
            for (label, validated), points in sorted(series.items(), key=validated_first):
                steps = sorted(points)
                colour, marker = styles(label)
                values += [points[s] for s in steps]
                axis.plot(steps, [points[s] for s in steps], marker=marker, markersize=4,
                          color=colour, linestyle="-" if validated else "--",
                          markerfacecolor=colour if validated else "none",
                          label=label + ("" if validated else " [unvalidated]"))
            positive = [v for v in values if v > 0]
            if metric == COLLIDE_TIME and positive and max(positive) / min(positive) > 10:
                axis.set_yscale("log")  # rebuild spikes would flatten the rest
            axis.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
            axis.set_xlabel("step")
            axis.set_ylabel(ylabel)
            axis.set_title(title, fontsize="medium")
            axis.grid(True, which="major", alpha=0.5)
            legend_below(axis)
    finish_figure(figure, "collide: BVH update strategies on moving boxes, step by step "
                          "(a refitted tree ages: its quality ratio grows)")
    return [save_atomically(figure, os.path.join(out_dir, COLLIDE_DECAY_FILE))]


def collide_bv_points(rows, include_unvalidated):
    """{(params, n): [(label, candidate pairs, false-positive ratio, exact-pairs time (s),
    build time (s))]} of workload triangles, one point per (structure, bv); nan where a figure
    is missing (times follow the validation rule, pair counts and ratios do not)."""
    triangles = [row for row in rows if row.suite == COLLIDE_SUITE and row.workload == "triangles"]
    timing = collide_timing(triangles, include_unvalidated, "collide triangles timing",
                            metric=COLLIDE_TIME, operation=("build", "exact_pairs"))
    counts = [row for row in triangles if row.operation == "candidate_pairs"
              and row.metric in ("pairs", "false_positive_ratio")]
    cells = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in timing + counts:
        if row.metric == COLLIDE_TIME and row.unit not in UNIT_SECONDS:
            continue
        value = convert(row.value, row.unit, "s") if row.metric == COLLIDE_TIME else row.value
        label = row.bv if row.bv and row.structure == f"bvh_{row.bv}" else label_of(row)
        if row.metric == COLLIDE_TIME and not row.validated:
            label += " [unvalidated]"
        cells[(row.params, row.n, label)][(row.operation, row.metric)].append(value)
    out = collections.defaultdict(list)
    for (params, n, label), metrics in sorted(cells.items()):
        def get(operation, metric):
            values = metrics.get((operation, metric))
            return median(values) if values else float("nan")
        out[(params, n)].append((label, get("candidate_pairs", "pairs"),
                                 get("candidate_pairs", "false_positive_ratio"),
                                 get("exact_pairs", COLLIDE_TIME), get("build", COLLIDE_TIME)))
    return dict(out)


def plot_collide_bv_tradeoff(rows, out_dir, include_unvalidated):
    data = collide_bv_points(rows, include_unvalidated)
    groups = [g for g in sorted(data) if any(p[1] > 0 for p in data[g])]
    if not groups:
        note(f"skip {COLLIDE_BV_FILE}: no collide rows of workload triangles with candidate pairs")
        return []
    figure, axes = plt.subplots(len(groups), 2, squeeze=False, figsize=(14, 6 * len(groups)))
    for row_axes, group in zip(axes, groups):
        params, n = group
        where = f"{params} n={format_n(n)}" if params else f"n={format_n(n)}"

        def points(index):
            out = []
            for label, candidates, fp, *times in data[group]:
                if candidates > 0 and math.isfinite(times[index]) and times[index] > 0:
                    text = label + (f" (fp {fp:.2f})" if math.isfinite(fp) else "")
                    out.append((text, candidates, times[index]))
            return out

        for axis, index, what in ((row_axes[0], 0, "exact-pairs time"),
                                  (row_axes[1], 1, "build time")):
            drawn = points(index)
            if not drawn:
                axis.set_axis_off()
                axis.text(0.5, 0.5, f"{where}: no {what} rows", ha="center", va="center")
                continue
            draw_tradeoff_panel(axis, drawn,
                                "candidate pairs (BV overlaps reaching the exact test; "
                                "fp = false-positive ratio)",
                                f"{what} (s)", f"triangles {where}: {what} against candidate pairs")
    figure.suptitle("collide: what bounding-volume accuracy costs in time (triangle soup self-"
                    "intersection; one point per BVH volume type; lower-left is better)")
    figure.tight_layout(rect=(0, 0, 1, 1.0 - 0.5 / figure.get_figheight()))
    return [save_atomically(figure, os.path.join(out_dir, COLLIDE_BV_FILE))]


def scene_stage_times(rows, include_unvalidated):
    """{(scene, n): {(label, params, validated): {operation: median time (SCENE_UNIT)}}} of the
    scenes suite's time rows (per-step medians; SCENE_SKIP left out), and {same keys:
    steps_per_second} where measured."""
    scenes = [row for row in rows if row.suite == SCENES_SUITE]
    timing = collide_timing(scenes, include_unvalidated, "scenes timing", metric=COLLIDE_TIME)
    times = collections.defaultdict(lambda: collections.defaultdict(lambda: collections.defaultdict(list)))
    for row in timing:
        if row.operation in SCENE_SKIP or row.unit not in UNIT_SECONDS:
            continue
        times[(row.workload, row.n)][(label_of(row), row.params, row.validated)][row.operation] \
            .append(convert(row.value, row.unit, SCENE_UNIT))
    rates = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in scenes:
        if row.metric == COLLIDE_STEPS_PER_SECOND and (row.validated or include_unvalidated):
            rates[(row.workload, row.n)][(label_of(row), row.params, row.validated)].append(row.value)
    return ({scene: median_points(by_key) for scene, by_key in times.items()},
            {scene: {key: median(v) for key, v in by_key.items()} for scene, by_key in rates.items()})


def plot_scenes(rows, out_dir, include_unvalidated):
    times, rates = scene_stage_times(rows, include_unvalidated)
    panels = sorted(times, key=lambda k: (workload_sort_key(k[0]), k[1]))
    panels = [p for p in panels if any(set(stages) - {SCENE_TOTAL} for stages in times[p].values())]
    if not panels:
        note(f"skip {SCENES_FILE}: no per-stage time rows in suite {SCENES_SUITE}")
        return []
    present = {op for p in panels for stages in times[p].values() for op in stages} - {SCENE_TOTAL}
    order = [s for s in SCENE_STAGES if s in present] + sorted(present - set(SCENE_STAGES))
    cmap = plt.get_cmap("tab10")  # one colour per stage, the same in every scene
    known = list(SCENE_STAGES) + sorted(present - set(SCENE_STAGES))
    colours = {stage: cmap(known.index(stage) % 10) for stage in order}
    bars = max(len(times[p]) for p in panels)
    columns = min(MAX_COLUMNS, len(panels))
    nrows = math.ceil(len(panels) / columns)
    legend_inches = 0.2 * math.ceil((len(order) + 1) / LEGEND_COLUMNS) + 0.3
    figure, axes = plt.subplots(nrows, columns, squeeze=False,
                                figsize=(max(6.5, 1.5 + 1.1 * bars) * columns,
                                         (4.6 + legend_inches) * nrows + 0.6))
    axes = axes.ravel()
    for extra in axes[len(panels):]:
        extra.set_visible(False)
    for axis, panel in zip(axes, panels):
        scene, n = panel
        keys = sorted(times[panel], key=lambda k: (k[0], k[1], not k[2]))
        params = {k[1] for k in keys}
        shared = params.pop() if len(params) == 1 else None
        positions = np.arange(len(keys))
        bottom = np.zeros(len(keys))
        for stage in order:
            heights = np.array([times[panel][key].get(stage, 0.0) for key in keys])
            if not heights.any():
                continue
            axis.bar(positions, heights, 0.6, bottom=bottom, color=colours[stage], label=stage)
            bottom += heights
        totals = [times[panel][key].get(SCENE_TOTAL, np.nan) for key in keys]
        axis.scatter(positions, totals, marker="_", s=900, linewidths=2, color="black", zorder=3,
                     label=f"{SCENE_TOTAL} (total, not stacked)")
        tops = [max(t, b) if math.isfinite(t) else b for t, b in zip(totals, bottom)]
        for x, top, key in zip(positions, tops, keys):
            rate = rates.get(panel, {}).get(key)
            if rate is not None:
                axis.annotate(f"{rate:.3g} steps/s", (x, top), ha="center", fontsize=7,
                              xytext=(0, 4), textcoords="offset points")
        axis.set_ylim(0, max(tops) * 1.15)
        axis.set_xticks(positions)
        axis.set_xticklabels([label + ("" if shared is not None else f"\n{p}")
                              + ("" if validated else "\n[unvalidated]")
                              for label, p, validated in keys], fontsize="small")
        axis.set_ylabel(f"median time per step ({SCENE_UNIT})")
        title = f"{scene}, n={format_n(n)}"
        if shared:
            title += "\n" + shared
        axis.set_title(title, fontsize="medium")
        axis.grid(True, axis="y", alpha=0.5)
        axis.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=LEGEND_COLUMNS,
                    fontsize="small", frameon=False, markerscale=0.4)
    finish_figure(figure, "scenes: median time per step by stage (stacked)\nblack mark: median "
                          "whole step (not a sum of stage medians)")
    return [save_atomically(figure, os.path.join(out_dir, SCENES_FILE))]


def plot_collide(rows, out_dir, include_unvalidated):
    """The collide suite's figures; notes (no crash) for workloads it lacks."""
    collide = [row for row in rows if row.suite == COLLIDE_SUITE]
    if not collide:
        return []
    # One style per participant across the collide figures (triangles are labelled by BV).
    styles = StyleBook(label_of(row) for row in collide if row.workload != "triangles")
    target = COLLIDE_SPEEDUP_TARGET[1]
    for label in styles.styles:
        if label.split("<")[0] == target:
            styles.styles[label] = ("black", "*")  # the structure the targets are about
    written = []
    written += plot_collide_boxes(collide, out_dir, styles, include_unvalidated)
    written += plot_collide_moving(collide, out_dir, styles, include_unvalidated)
    written += plot_collide_refit_decay(collide, out_dir, styles, include_unvalidated)
    written += plot_collide_bv_tradeoff(collide, out_dir, include_unvalidated)
    return written


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--results", default=os.path.join(repo, "results"),
                        help="directory of *.csv tables (default: %(default)s)")
    parser.add_argument("--out", default=os.path.join(repo, "plots"),
                        help="directory for the PNGs (default: %(default)s)")
    parser.add_argument("--include-unvalidated", action="store_true",
                        help="draw timing rows with validated=false hollow/dashed "
                             "instead of skipping them")
    args = parser.parse_args(argv)

    rows = read_results(args.results)
    if not rows:
        note("no rows to plot")
        return 0
    os.makedirs(args.out, exist_ok=True)
    styles = StyleBook({label_of(row) for row in rows} | {series_label(row) for row in rows})
    written = []
    written += plot_complexity(rows, args.out, styles, args.include_unvalidated)
    written += plot_recall_vs_time(rows, args.out, styles, args.include_unvalidated)
    written += plot_raycast(rows, args.out, styles, args.include_unvalidated)
    written += plot_ratios(rows, args.out, styles, args.include_unvalidated)
    written += plot_bv_tradeoff(rows, args.out, args.include_unvalidated)
    written += plot_bvh_tradeoff(rows, args.out, args.include_unvalidated)
    written += plot_collide(rows, args.out, args.include_unvalidated)
    if any(row.suite == SCENES_SUITE for row in rows):
        written += plot_scenes(rows, args.out, args.include_unvalidated)
    note(f"{len(written)} PNG(s) written to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
