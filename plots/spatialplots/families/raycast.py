"""Ray casting: raycast_time_per_ray.png.

One subplot per ray kind (the params of operation ray: incoherent, coherent camera rays, rays
on objects=boxes, thick rays on objects=points), log-log time per ray against n (triangles).
Colour is the structure; the line style is the generated workload (sphere solid, soup dashed,
others dotted) with the fitted exponent in the legend; real meshes are unconnected crosses at
their n.  Timings follow the validation rule; repeated runs of a point give their median.
(The raycast suite's generic build/ray curves come from the complexity family.)
"""

import collections
import math
import os

from ..core import common_unit, convert, fit_exponent, label_of, median, split_validated
from ..family import figure_family
from ..figures import (finish_figure, legend_below, log_log_grid, new_figure, plot_series,
                       save_atomically)

RAYCAST_FILE = "raycast_time_per_ray.png"
RAYCAST_LINESTYLES = {"sphere": "-", "soup": "--"}  # other generated workloads: dotted
REAL_PREFIX = "real:"


def raycast_series(rows, include_unvalidated=False):
    """{params: {(structure label, workload, validated): {n: median time}}}, and the unit.

    From the operation=ray, metric=time_per_op rows, following the validation rule."""
    timing = [row for row in rows if row.operation == "ray" and row.metric == "time_per_op"
              and row.value > 0]
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


@figure_family("raycast", suites=("raycast",), order=30)
def draw(ctx):
    """Time per ray against mesh size, one panel per ray kind."""
    series, unit = raycast_series(ctx.rows, ctx.include_unvalidated)
    if not series:
        return []
    panels = sorted(series)
    entries = max(len({(label, workload) for label, workload, _ in by_key})
                  for by_key in series.values())
    figure, axes = new_figure(len(panels), entries, one_column=True)
    for axis, params in zip(axes, panels):
        real_labelled = set()
        for (label, workload, validated), points in sorted(series[params].items(),
                                                           key=lambda item: tuple(map(str, item[0]))):
            ns = sorted(points)
            times = [points[n] for n in ns]
            suffix = "" if validated else " [unvalidated]"
            if workload.startswith(REAL_PREFIX):
                text = f"{label} real meshes{suffix}" if (label, validated) not in real_labelled else None
                real_labelled.add((label, validated))
                plot_series(axis, ns, times, label, validated, ctx.styles, linestyle="none",
                            marker="x", label=text)
                continue
            exponent = fit_exponent(ns, times)
            text = f"{label} {workload}{suffix}"
            text += f" (n^{exponent:.2f})" if math.isfinite(exponent) else ""
            plot_series(axis, ns, times, label, validated, ctx.styles, label=text,
                        linestyle=RAYCAST_LINESTYLES.get(workload, ":"))
        log_log_grid(axis)
        axis.set_title(params or "rays")
        axis.set_xlabel("n (triangles)")
        axis.set_ylabel(f"time per ray ({unit})")
        legend_below(axis)
    finish_figure(figure, "raycast: time per ray against mesh size (median of repetitions)")
    drawn = [row for row in ctx.rows if row.operation == "ray" and row.metric == "time_per_op"
             and row.value > 0 and (row.validated or ctx.include_unvalidated)]
    return [save_atomically(figure, os.path.join(ctx.out_dir, RAYCAST_FILE), rows=drawn)]
