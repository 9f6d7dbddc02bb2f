"""Complexity curves: <suite>[_<bv>]_<operation>[_<params>]_<dim>d_<scalar>.png.

One figure per (suite, operation, params, dim, scalar, time metric), one subplot per workload
(`uniform` first; a workload needs two distinct n), log-log time against n with one line per
structure.  The legend gives the least-squares slope of log(time) on log(n) ("kd_tree (n^0.12)");
a grey dashed line shows the theoretical growth from the registry's `complexity` entries,
anchored at the smallest-n point of the fastest structure whose theory is the suite
baseline's (so an oracle's trivially fast linear "build" does not turn the n log n line into
an n line).  Suites with `series_params` in the registry (bv: `method`) are split by the `bv`
column into one figure per volume type, the params naming the curves.  When one operation has
two time metrics, the metric is added to the file name.  Suites claimed by an exclusive family
(collide, scenes) are not drawn here.
"""

import collections
import os

from ..core import (TIME_METRICS, METRIC_LABELS, common_unit, convert, figure_params, format_n,
                    series_label, slug, unique_name, split_validated, workload_sort_key)
from ..family import figure_family
from ..figures import draw_complexity_panel, finish_figure, new_figure, save_atomically
from ..io import note


def figure_groups(rows, registry):
    """{(suite, operation, params, dim, scalar, metric, bv): [rows]} of the positive timing
    rows; bv is "" unless the suite has series_params."""
    figures = collections.defaultdict(list)
    for row in rows:
        bv = row.bv if registry.series_params(row.suite) else ""
        figures[(row.suite, row.operation, figure_params(row, registry), row.dim, row.scalar,
                 row.metric, bv)].append(row)
    return figures


def file_names(keys):
    """Base file name per figure key (duplicates resolved later by the metric suffix)."""
    names = {}
    for key in keys:
        suite, operation, params, dim, scalar, _metric, bv = key
        parts = [suite] + ([bv] if bv else []) + [operation] + ([slug(params)] if params else []) \
            + [f"{dim}d", scalar]
        names[key] = "_".join(slug(part) for part in parts) + ".png"
    return names


@figure_family("complexity", order=10)
def draw(ctx):
    """Time against n per structure, with fitted exponents and the theory line."""
    timing = [row for row in ctx.rows if row.metric in TIME_METRICS]
    non_positive = [row for row in timing if row.value <= 0]
    if non_positive:
        note(f"skipped {len(non_positive)} timing row(s) with value <= 0 (no place on log axes)")
    timing = [row for row in timing if row.value > 0]
    timing = split_validated(timing, ctx.include_unvalidated, "timing")

    figures = figure_groups(timing, ctx.registry)
    base_names = file_names(figures)
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
            series_key = (series_label(row, ctx.registry), row.validated)
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
            draw_complexity_panel(axis, panels[workload], operation, metric, unit, workload,
                                  ctx.styles, ctx.registry, suite)
        title = f"{suite}: " + (f"{bv} " if bv else "") + operation + (f" ({params})" if params else "")
        title += f" \u2014 {METRIC_LABELS.get(metric, metric)}, {dim}D, {scalar}"
        finish_figure(figure, title)
        drawn = [row for row in figure_rows if row.workload in kept]
        written.append(save_atomically(figure, os.path.join(ctx.out_dir, name), rows=drawn))
    return written
