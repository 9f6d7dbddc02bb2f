"""Shared helpers without drawing: params, names, units, statistics and the validation rule.

Validation rule: a timing row whose `validated` column is not true is skipped (split_validated),
because the harness never times a wrong answer and a row that was not checked against the
oracle cannot be compared with one that was.  With --include-unvalidated such rows are kept and
drawn hollow and dashed, labelled "[unvalidated]".  Accuracy rows (recall, pair counts,
false-positive ratios, tree quality) are used whatever their flag.
"""

import math
import os
import re

import numpy as np

from .io import note

TIME_METRICS = {"time_per_op", "build_time", "fit_time"}
# The collide and scenes suites' metrics: median seconds (per step where stepped), and rates.
TIME = "time"
STEPS_PER_SECOND = "steps_per_second"

METRIC_LABELS = {
    "time_per_op": "time per operation",
    "fit_time": "fit time",
    "build_time": "build time",
    "recall": "recall",
    "time_ratio": "time ratio",
}

# Theory keys (registry `complexity` values) -> growth as a function of n.
COMPLEXITY_FUNCTIONS = {
    "1": lambda n: np.ones_like(n, dtype=float),
    "log n": lambda n: np.log(n),  # the base cancels once the line is anchored
    "n": lambda n: np.asarray(n, dtype=float),
    "n log n": lambda n: n * np.log(n),
    "n^2": lambda n: np.asarray(n, dtype=float) ** 2,
}

# Workloads in this order first; others (real:<file>, ...) alphabetically after them.
WORKLOAD_ORDER = ["uniform", "clusters", "sphere", "plane", "line", "lattice", "duplicates", "clusters_far"]

UNIT_SECONDS = {"ns": 1e-9, "us": 1e-6, "\u00b5s": 1e-6, "ms": 1e-3, "s": 1.0}


# -------------------------------------------------------------------------------- statistics

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


def median(values):
    return float(np.median(np.asarray(values, dtype=float)))


def geometric_mean(values):
    values = [v for v in values if v > 0 and math.isfinite(v)]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else float("nan")


def arithmetic_mean(values):
    values = [v for v in values if math.isfinite(v)]
    return sum(values) / len(values) if values else float("nan")


def pareto_front(points):
    """Indices of the points not dominated in (x, y), both to be minimised, sorted by x."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best_y = [], float("inf")
    for i in order:
        if points[i][1] < best_y:
            front.append(i)
            best_y = points[i][1]
    return front


def median_points(series):
    """{key: {x: [values]}} -> {key: {x: median}}."""
    return {key: {x: median(values) for x, values in points.items()}
            for key, points in series.items()}


def fastest_series(series):
    """Key of the fastest series: lowest time at the largest n they all share."""
    shared = set.intersection(*(set(points) for points in series.values()))
    if shared:
        n = max(shared)
        return min(series, key=lambda key: series[key][n])
    # No common n: compare the geometric means.
    return min(series, key=lambda key: np.mean(np.log(list(series[key].values()))))


def validated_first(item):
    """Sort key of ((label, validated), points) items: by label, validated before not."""
    (label, validated), _ = item
    return (label, not validated)


# -------------------------------------------------------------------------------- params, names

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


def without_params(params, keys):
    """params with the given keys removed: ('a=1;step=3', ('step',)) -> 'a=1'."""
    return format_params([(k, v) for k, v in parse_params(params) if k not in keys])


def slug(text):
    """File-name-safe form: 'k=10;eps=0.5' -> 'k10_eps0.5', 'real:bunny.off' -> 'real-bunny.off'."""
    text = text.replace(";", "_").replace("=", "").replace(":", "-")
    text = re.sub(r"[^A-Za-z0-9._+-]+", "-", text)
    return text.strip("-_") or "none"


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


def format_n(n):
    exponent = math.log10(n) if n > 0 else 0.0
    if n >= 1000 and abs(exponent - round(exponent)) < 1e-12:
        return f"1e{int(round(exponent))}"
    return f"{n:,}"


def label_of(row):
    """Series label: the structure, with its bounding-volume type when there is one."""
    return f"{row.structure}<{row.bv}>" if row.bv else row.structure


def structure_of(label):
    """The structure a label names: 'bvh<obb>' -> 'bvh', 'spatialbench dito' -> 'spatialbench',
    'fcl_sap [unvalidated]' -> 'fcl_sap'."""
    return label.split("<")[0].split(" ")[0]


def series_label(row, registry):
    """Label of a curve: label_of(row), or for a suite with series_params (registry) the
    structure followed by those params' values ("spatialbench dito")."""
    keys = registry.series_params(row.suite)
    if not keys:
        return label_of(row)
    named = dict(parse_params(row.params))
    return " ".join([row.structure] + [named[key] for key in keys if key in named])


def figure_params(row, registry):
    """The params that select a figure (the suite's series_params removed)."""
    return without_params(row.params, registry.series_params(row.suite))


def workload_sort_key(workload):
    if workload in WORKLOAD_ORDER:
        return (0, WORKLOAD_ORDER.index(workload), workload)
    return (1, 0, workload)


# -------------------------------------------------------------------------------- units

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


# -------------------------------------------------------------------------------- validation

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


def select_timing(rows, include_unvalidated, what, **selection):
    """Positive rows matching selection (field=value; a tuple value means any of), following
    the validation rule."""
    picked = [row for row in rows
              if all(getattr(row, field) in value if isinstance(value, tuple)
                     else getattr(row, field) == value for field, value in selection.items())
              and row.value > 0]
    return split_validated(picked, include_unvalidated, what)
