"""Accuracy against time: <suite>_recall_vs_time_<workload>_<dim>d_<scalar>.png.

For the approximate kNN rows (operation approx_knn, params with eps=): recall on y against
time per query on a log x axis, at the largest n of the group, one curve per structure through
its eps values, each point labelled with its eps.  A point needs a time_per_op row and a recall
row with the same structure, workload, n, dim, scalar and params.  When the curves differ in
other params (k), those are added to the legend.  Recall is used whatever its validated flag
(it is the comparison with the oracle); the time follows the validation rule.
"""

import collections
import os

from ..core import (common_unit, convert, format_n, format_params, label_of, median,
                    parse_params, slug, split_validated, workload_sort_key)
from ..family import figure_family
from ..figures import log_log_grid, new_figure, plot_series, save_atomically
from ..io import note

APPROX_OPERATION = "approx_knn"
RECALL_METRIC = "recall"


def recall_figures(rows, include_unvalidated):
    """({(suite, workload, dim, scalar): {n: [(label, other params, eps value, eps text,
    time rows, median recall)]}}, {same key: time units}); None when there is nothing."""
    approx = [row for row in rows if row.operation == APPROX_OPERATION
              and any(key == "eps" for key, _ in parse_params(row.params))]
    times = [row for row in approx if row.metric == "time_per_op" and row.value > 0]
    times = split_validated(times, include_unvalidated, f"{APPROX_OPERATION} timing")
    recalls = [row for row in approx if row.metric == RECALL_METRIC]
    if not times or not recalls:
        if approx:
            note(f"skip recall-vs-time plots: {APPROX_OPERATION} rows lack "
                 f"{'time_per_op' if not times else RECALL_METRIC}")
        return None

    def point_key(row):
        return (row.suite, row.workload, row.dim, row.scalar, row.n, label_of(row), row.params)

    time_values = collections.defaultdict(list)
    for row in times:
        time_values[point_key(row)].append(row)
    recall_values = collections.defaultdict(list)
    for row in recalls:
        recall_values[point_key(row)].append(row.value)

    figures = collections.defaultdict(lambda: collections.defaultdict(list))
    units = collections.defaultdict(set)
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
        units[(suite, workload, dim, scalar)].update(row.unit for row in time_rows)
    return figures, units


@figure_family("recall_vs_time", order=20)
def draw(ctx):
    """Recall against time per query for approximate kNN, one curve per structure."""
    found = recall_figures(ctx.rows, ctx.include_unvalidated)
    if found is None:
        return []
    figures, time_units = found
    written = []
    for key in sorted(figures, key=lambda k: (k[0], workload_sort_key(k[1]), k[2], k[3])):
        suite, workload, dim, scalar = key
        n = max(figures[key])
        unit = common_unit(time_units[key])
        if unit is None:
            note(f"skip recall vs time {suite} {workload}: mixed time units")
            continue
        curves = collections.defaultdict(list)
        drawn = []
        for label, others, eps_value, eps, time_rows, recall in figures[key][n]:
            drawn += time_rows
            time = median([convert(row.value, row.unit, unit) for row in time_rows])
            validated = all(row.validated for row in time_rows)
            curves[(label, others, validated)].append((eps_value, eps, time, recall))
        several_others = len({others for _, others, _ in curves}) > 1

        figure, (axis,) = new_figure(1)
        for (label, others, validated) in sorted(curves, key=lambda k: (k[0], k[1], not k[2])):
            points = sorted(curves[(label, others, validated)])
            text = label + (f" {others}" if several_others and others else "")
            text += "" if validated else " [unvalidated]"
            colour, _ = ctx.styles(label)
            plot_series(axis, [p[2] for p in points], [p[3] for p in points], label, validated,
                        ctx.styles, label=text)
            for _, eps, time, recall in points:
                axis.annotate(eps, (time, recall), textcoords="offset points",
                              xytext=(4, -9), fontsize=7, color=colour)
        log_log_grid(axis, log_y=False)
        low = min(min(p[3] for p in points) for points in curves.values())
        axis.set_ylim(min(0.0, low) - 0.02, 1.05)
        axis.set_xlabel(f"time per query ({unit})")
        axis.set_ylabel("recall (ratio)")
        others_all = {others for _, others, _ in curves}
        shared = f" ({others_all.pop()})" if len(others_all) == 1 and "" not in others_all else ""
        axis.set_title(f"{suite}: approximate kNN{shared}, recall vs time\n"
                       f"{workload}, n={format_n(n)}, {dim}D, {scalar}")
        # Lower right stays empty on a recall/time front (slow answers are accurate ones).
        axis.legend(fontsize="small", loc="lower right", title="point labels: eps",
                    title_fontsize="small")
        figure.tight_layout()
        name = f"{slug(suite)}_recall_vs_time_{slug(workload)}_{dim}d_{slug(scalar)}.png"
        written.append(save_atomically(figure, os.path.join(ctx.out_dir, name), rows=drawn))
    return written
