"""Scene pipelines (scenes suite): scenes.png.

One subplot per scene (the `workload` column) and n.  Each structure gets a bar stacking the
median per-step times of the stages, in the order of the suite's registry `stages` (motion,
churn, update, collide_pairs, ...); other operations with a time row are stacked after
them, except the registry's `once_stages` (build: once per scene, not per step).  A stage keeps
its colour in every subplot, so the bars show which stages each scene runs.  The registry's
`total_stage` (step, the whole step) is not stacked: it is a black mark labelled with the steps
per second, the median of whole steps rather than a sum of stage medians, so it may lie above
the stack.
"""

import collections
import math
import os

import matplotlib.pyplot as plt
import numpy as np

from ..core import (STEPS_PER_SECOND, TIME, UNIT_SECONDS, convert, format_n, label_of, median,
                    median_points, select_timing, workload_sort_key)
from ..family import figure_family
from ..figures import (MAX_COLUMNS, finish_figure, legend_below, legend_inches,
                       save_atomically)
from ..io import note

SUITE = "scenes"  # the suite this family draws (exclusively: no generic curves)
SCENES_FILE = "scenes.png"
SCENE_UNIT = "ms"


def scene_stage_times(rows, suite, include_unvalidated):
    """{(scene, n): {(label, params, validated): {operation: median time (SCENE_UNIT)}}} of the
    time rows (per-step medians; the suite's once_stages left out), and {same keys:
    steps_per_second} where measured.  `suite` is the registry's Suite entry."""
    timing = select_timing(rows, include_unvalidated, "scenes timing", metric=TIME)
    times = collections.defaultdict(lambda: collections.defaultdict(lambda: collections.defaultdict(list)))
    for row in timing:
        if row.operation in suite.once_stages or row.unit not in UNIT_SECONDS:
            continue
        times[(row.workload, row.n)][(label_of(row), row.params, row.validated)][row.operation] \
            .append(convert(row.value, row.unit, SCENE_UNIT))
    rates = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in rows:
        if row.metric == STEPS_PER_SECOND and (row.validated or include_unvalidated):
            rates[(row.workload, row.n)][(label_of(row), row.params, row.validated)].append(row.value)
    return ({scene: median_points(by_key) for scene, by_key in times.items()},
            {scene: {key: median(v) for key, v in by_key.items()} for scene, by_key in rates.items()})


@figure_family("scenes", suites=(SUITE,), exclusive=True, order=80)
def draw(ctx):
    """Per scene, the median time per step of each stage, stacked, per structure."""
    suite = ctx.registry.suite(SUITE)
    total = suite.total_stage
    times, rates = scene_stage_times(ctx.rows, suite, ctx.include_unvalidated)
    panels = sorted(times, key=lambda k: (workload_sort_key(k[0]), k[1]))
    panels = [p for p in panels if any(set(stages) - {total} for stages in times[p].values())]
    if not panels:
        note(f"skip {SCENES_FILE}: no per-stage time rows in suite {SUITE}")
        return []
    present = {op for p in panels for stages in times[p].values() for op in stages} - {total}
    order = [s for s in suite.stages if s in present] + sorted(present - set(suite.stages))
    cmap = plt.get_cmap("tab10")  # one colour per stage, the same in every scene
    known = list(suite.stages) + sorted(present - set(suite.stages))
    colours = {stage: cmap(known.index(stage) % 10) for stage in order}
    most_bars = max(len(times[p]) for p in panels)
    columns = min(MAX_COLUMNS, len(panels))
    nrows = math.ceil(len(panels) / columns)
    figure, axes = plt.subplots(nrows, columns, squeeze=False,
                                figsize=(max(6.5, 1.5 + 1.1 * most_bars) * columns,
                                         (4.6 + legend_inches(len(order) + 1)) * nrows + 0.6))
    axes = axes.ravel()
    for extra in axes[len(panels):]:
        extra.set_visible(False)
    for axis, panel in zip(axes, panels):
        draw_scene_panel(axis, panel, times[panel], rates.get(panel, {}), order, colours, total)
    finish_figure(figure, "scenes: median time per step by stage (stacked)\nblack mark: median "
                          "whole step (not a sum of stage medians)")
    return [save_atomically(figure, os.path.join(ctx.out_dir, SCENES_FILE))]


def draw_scene_panel(axis, panel, times, rates, order, colours, total):
    scene, n = panel
    keys = sorted(times, key=lambda k: (k[0], k[1], not k[2]))
    params = {k[1] for k in keys}
    shared = params.pop() if len(params) == 1 else None
    positions = np.arange(len(keys))
    bottom = np.zeros(len(keys))
    for stage in order:
        heights = np.array([times[key].get(stage, 0.0) for key in keys])
        if not heights.any():
            continue
        axis.bar(positions, heights, 0.6, bottom=bottom, color=colours[stage], label=stage)
        bottom += heights
    totals = [times[key].get(total, np.nan) for key in keys]
    if total:
        axis.scatter(positions, totals, marker="_", s=900, linewidths=2, color="black", zorder=3,
                     label=f"{total} (total, not stacked)")
    tops = [max(t, b) if math.isfinite(t) else b for t, b in zip(totals, bottom)]
    for x, top, key in zip(positions, tops, keys):
        rate = rates.get(key)
        if rate is not None:
            axis.annotate(f"{rate:.3g} steps/s", (x, top), ha="center", fontsize=7,
                          xytext=(0, 4), textcoords="offset points")
    axis.set_ylim(0, max(tops) * 1.15)
    axis.set_xticks(positions)
    axis.set_xticklabels([label + ("" if shared is not None else f"\n{p}")
                          + ("" if validated else "\n[unvalidated]")
                          for label, p, validated in keys], fontsize="small")
    axis.set_ylabel(f"median time per step ({SCENE_UNIT})")
    axis.set_title(f"{scene}, n={format_n(n)}" + (f"\n{shared}" if shared else ""),
                   fontsize="medium")
    axis.grid(True, axis="y", alpha=0.5)
    legend_below(axis, markerscale=0.4)
