"""Bounding volumes, accuracy against time: bv_tradeoff.png (bv suite).

Three panels, one point per volume type x fitting method (x overlap test), each the geometric
mean over the suite's shapes:
1. tightness (volume / convex hull volume, lower is tighter) against fit time at n = 1e5
   (else the largest n measured);
2. the same tightness against the time of one overlap test;
3. false_positive_rate_shapes (pairs whose volumes overlap although the enclosed shapes are
   disjoint: the work a BVH cannot prune; arithmetic mean, 0 drawn at 1e-4) against the
   overlap-test time.
Stars and a dashed step line mark the Pareto front.  Points of a structure whose registry kind
is not "library" (CGAL's fits) carry "[<structure>]" in their label.  The per-type fit-time
curves (bv_<type>_fit_...) come from the complexity family.
"""

import collections
import math
import os

import matplotlib.pyplot as plt

from ..core import arithmetic_mean, geometric_mean, median, parse_params
from ..family import figure_family
from ..figures import draw_tradeoff_panel, save_atomically
from ..io import note

BV_TRADEOFF_FILE = "bv_tradeoff.png"
BV_REFERENCE_N = 100000  # fit figures are compared at this n (else the largest n measured)


def bv_points(rows, registry, operation, x_metric, y_metric, n_choice, extra_params=(),
              y_mean=geometric_mean):
    """(label, x, y) per (structure, bv, series params[, extra params]): the geometric mean
    over workloads of the median x, and y_mean (geometric by default; arithmetic for rates,
    which may be 0) of the median y, at one n per workload (n_choice picks it from the ns
    measured).  The series params are the suite's (registry), e.g. method."""
    cells = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in rows:
        if row.operation != operation or row.metric not in (x_metric, y_metric):
            continue
        named = dict(parse_params(row.params))
        group = tuple(registry.series_params(row.suite)) + tuple(extra_params)
        key = (row.structure, row.bv) + tuple(named.get(k, "") for k in group)
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
        label = f"{bv} {' '.join(r for r in rest if r)}" + (
            "" if registry.kind(structure) == "library" else f" [{structure}]")
        points.append((label, geometric_mean(xs), y_mean(ys)))
    return [p for p in points if math.isfinite(p[1]) and math.isfinite(p[2])]


@figure_family("bv_tradeoff", suites=("bv",), order=50)
def draw(ctx):
    """Tightness and pruning power of each volume type against fit and overlap-test time."""
    bv_rows = [row for row in ctx.rows if row.validated or ctx.include_unvalidated]

    def at_reference_n(ns):
        return BV_REFERENCE_N if BV_REFERENCE_N in ns else max(ns)

    fit = bv_points(bv_rows, ctx.registry, "fit", "fit_time", "tightness", at_reference_n)
    overlap = bv_points(bv_rows, ctx.registry, "overlap", "time_per_op",
                        "false_positive_rate_shapes", max, ("test",), y_mean=arithmetic_mean)
    tight_by_method = {label.split(" [")[0]: y for label, _, y in fit}
    overlap_tight = []
    for label, x, _ in overlap:
        key = " ".join(label.split(" ")[:2])  # "<bv> <method>"
        if key in tight_by_method:
            overlap_tight.append((label, x, tight_by_method[key]))
    if not (fit or overlap_tight or overlap):
        note(f"skip {BV_TRADEOFF_FILE}: no fit/overlap rows with both time and accuracy")
        return []
    figure, axes = plt.subplots(1, 3, figsize=(19, 6.5), squeeze=False)
    axes = axes[0]
    tightness = "tightness: volume / convex hull volume"
    if fit:
        draw_tradeoff_panel(axes[0], fit, "fit time (s), n = 1e5 where measured", tightness,
                            "tightness against fit time")
    if overlap_tight:
        draw_tradeoff_panel(axes[1], overlap_tight, "overlap test time (ns)", tightness,
                            "tightness against overlap-test time")
    if overlap:
        y = [(label, x, max(v, 1e-4)) for label, x, v in overlap]
        draw_tradeoff_panel(axes[2], y, "overlap test time (ns)",
                            "false-positive rate vs. the enclosed shapes\n"
                            "(mean over shapes; 0 drawn at 1e-4)",
                            "pruning power against overlap-test time")
    figure.suptitle("bv: accuracy against time (times and tightness: geometric means over "
                    "shapes; lower-left is better; stars = Pareto front)")
    figure.tight_layout()
    return [save_atomically(figure, os.path.join(ctx.out_dir, BV_TRADEOFF_FILE), rows=bv_rows)]
