"""Collision (collide suite): collide_boxes.png, collide_moving.png, collide_refit_decay.png and
collide_bv_tradeoff.png.  Times are the CSV's medians over repetitions; repeated runs of a
point are reduced to their median.  A missing workload gives a "skip collide_....png" note.

* collide_boxes.png, workload boxes, one row per (params, dim, scalar): build + all pairs
  (build_and_self_pairs) against n with fitted exponents and the registry's theory line; and
  the speed-up time(baseline) / time at each n both were measured, the baseline being the
  suite's registry `baseline` (cgal_box_intersection), with a dotted 1x line and a red dashed
  line per `speedup` target of the registry; a target's structure is drawn thick, black, with
  its speed-up printed at each point.
* collide_moving.png, workload moving_boxes: steps per second (1 / median step: move every box,
  update the structure, report all pairs) per participant, bars grouped by n (each group only
  the participants measured at that n), log y, pairs changed per step in the tick labels, a
  red dashed line per `steps_per_second` target.
* collide_refit_decay.png: the per-step rows of moving_boxes (params ...;step=K), per n tree
  quality (SAH node-area sum / root area) and step time against the step.
* collide_bv_tradeoff.png, workload triangles: exact-pairs time and build time against
  candidate pairs, one point per BVH volume type (a row whose bv is its structure's registry
  `bv` is labelled by the volume type alone), false-positive ratio in the label, Pareto front
  starred.
"""

import collections
import math
import os

import matplotlib.pyplot as plt
import matplotlib.ticker
import numpy as np

from ..core import (STEPS_PER_SECOND, TIME, UNIT_SECONDS, convert, format_n, label_of, median,
                    median_points, parse_params, select_timing, structure_of, validated_first,
                    without_params)
from ..family import figure_family
from ..figures import (bars, draw_complexity_panel, draw_tradeoff_panel, emphasise, empty_panel,
                       finish_figure, legend_below, legend_inches, log_log_grid, plot_series,
                       save_atomically)
from ..io import note

SUITE = "collide"  # the suite this family draws (exclusively: no generic curves)
BOXES_FILE = "collide_boxes.png"
MOVING_FILE = "collide_moving.png"
DECAY_FILE = "collide_refit_decay.png"
BV_FILE = "collide_bv_tradeoff.png"
SPEEDUP = "speedup"  # registry target metric of the boxes figure
STEP_PARAM = "step"  # params key of the per-step rows of moving_boxes


def speedups(series, baseline):
    """{(label, validated): {n: time(baseline) / time(label)}} at every n both were measured.

    series: {(label, validated): {n: time}}; the baseline is the series whose structure (label
    without <bv>) is `baseline`, its validated series preferred.  The baseline itself is left
    out; {} without a baseline."""
    keys = [key for key in series if structure_of(key[0]) == baseline]
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


def targets(registry, suite, metric, workload):
    entry = registry.suite(suite)
    return [t for t in (entry.targets_for(metric) if entry else [])
            if t.workload in ("", workload)]


def target_text(target, constructed):
    return "target: " + (target.label or constructed)


def collide_boxes_series(rows, include_unvalidated):
    """{(params, dim, scalar): {(label, validated): {n: [time (s)]}}} of the static boxes
    workload, operation build_and_self_pairs (build + all pairs)."""
    timing = select_timing(rows, include_unvalidated, "collide boxes timing", workload="boxes",
                           operation="build_and_self_pairs", metric=TIME)
    out = collections.defaultdict(lambda: collections.defaultdict(lambda: collections.defaultdict(list)))
    for row in timing:
        if row.unit in UNIT_SECONDS:
            out[(row.params, row.dim, row.scalar)][(label_of(row), row.validated)][row.n].append(
                convert(row.value, row.unit, "s"))
    return out


def plot_collide_boxes(ctx, suite, styles):
    data = collide_boxes_series(ctx.rows, ctx.include_unvalidated)
    if not data:
        note(f"skip {BOXES_FILE}: no collide rows of workload boxes, "
             f"operation build_and_self_pairs, metric time")
        return []
    baseline = ctx.registry.baseline(suite)
    goals = targets(ctx.registry, suite, SPEEDUP, "boxes")
    goal_structures = {t.structure for t in goals if t.structure}
    configs = sorted(data, key=lambda k: tuple(map(str, k)))
    entries = max(len(series) for series in data.values()) + 1 + len(goals)
    figure, axes = plt.subplots(len(configs), 2, squeeze=False,
                                figsize=(13, (4.6 + legend_inches(entries)) * len(configs) + 0.6))
    for (left, right), config in zip(axes, configs):
        params, dim, scalar = config
        series = data[config]
        where = f"boxes ({params}), {dim}D, {scalar}" if params else f"boxes, {dim}D, {scalar}"
        draw_complexity_panel(left, series, "build_and_self_pairs", TIME, "s", where, styles,
                              ctx.registry, suite)
        left.set_xlabel("n (boxes)")
        left.set_ylabel("build + all pairs time (s)")
        left.set_title(f"{where}\nbuild + self pairs, legend: fitted exponent", fontsize="medium")
        for structure in goal_structures:
            emphasise(left, structure)
        legend_below(left)

        ratios = speedups(median_points(series), baseline)
        if not ratios:
            note(f"{BOXES_FILE}: no {baseline or 'baseline'} rows for {where}, no speed-up panel")
            empty_panel(right, f"no {baseline or 'baseline'} rows:\nno speed-up")
            continue
        for (label, validated), points in sorted(ratios.items(), key=validated_first):
            ns = sorted(points)
            plot_series(right, ns, [points[n] for n in ns], label, validated, styles,
                        label=label + ("" if validated else " [unvalidated]"))
            if structure_of(label) in goal_structures:
                for n in ns:
                    right.annotate(f"{points[n]:.3g}x", (n, points[n]), fontsize=7,
                                   color=styles(label)[0], xytext=(0, 6),
                                   textcoords="offset points", ha="center")
        right.axhline(1.0, color="grey", linestyle=":", linewidth=1.0, label=f"{baseline} (1x)")
        for goal in goals:
            right.axhline(goal.value, color="red", linestyle="--", linewidth=1.0,
                          label=target_text(goal, f"{goal.structure} \u2265 {goal.value:g}x "
                                                  f"at n={format_n(goal.n)}"))
        log_log_grid(right)
        right.margins(x=0.08, y=0.12)
        for structure in goal_structures:
            emphasise(right, structure)
        right.set_xlabel("n (boxes)")
        right.set_ylabel(f"speed-up: {baseline} time / time (ratio)")
        right.set_title(f"{where}\nspeed-up over {baseline} (above 1: faster)", fontsize="medium")
        legend_below(right)
    finish_figure(figure, "collide: static self-intersection of n random boxes "
                          "(build + all pairs, median of repetitions)")
    return [save_atomically(figure, os.path.join(ctx.out_dir, BOXES_FILE),
                            rows=workload_rows(ctx, "boxes"))]


def collide_moving_bars(rows, include_unvalidated):
    """Steps per second of moving_boxes (operation update_and_self_pairs, the rows without a
    step= param): (groups [(n, params)] in order, {(label, validated): {group: median}},
    {group: median pairs changed per step})."""
    moving = [row for row in rows if row.workload == "moving_boxes"
              and row.operation == "update_and_self_pairs"
              and STEP_PARAM not in dict(parse_params(row.params))]
    rates = select_timing(moving, include_unvalidated, "collide moving_boxes steps/s",
                          metric=STEPS_PER_SECOND)
    values = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in rates:
        values[(label_of(row), row.validated)][(row.n, row.params)].append(row.value)
    changed = collections.defaultdict(list)
    for row in moving:
        if row.metric == "pairs_changed_per_step":
            changed[(row.n, row.params)].append(row.value)
    groups = sorted({group for points in values.values() for group in points})
    return groups, median_points(values), {g: median(v) for g, v in changed.items()}


def plot_collide_moving(ctx, suite, styles):
    groups, rates, changed = collide_moving_bars(ctx.rows, ctx.include_unvalidated)
    if not groups:
        note(f"skip {MOVING_FILE}: no collide rows of workload moving_boxes with "
             f"metric {STEPS_PER_SECOND}")
        return []
    several_params = len({params for _, params in groups}) > 1
    participants = sorted(rates, key=lambda key: (key[0], not key[1]))
    # Each group packs only the participants measured at its n (peers may stop early), so
    # every group is as wide as the widest one and the bars of a group are adjacent.
    present = {group: [key for key in participants if group in rates[key]] for group in groups}
    width = 0.85 / max(len(keys) for keys in present.values())
    positions = np.arange(len(groups))
    figure, axis = plt.subplots(figsize=(max(9.0, 1.5 + 0.32 * sum(map(len, present.values()))), 7.5))
    for key in participants:
        label, validated = key
        xs, heights = [], []
        for g, group in enumerate(groups):
            if group in rates[key]:
                i = present[group].index(key)
                xs.append(positions[g] + (i - (len(present[group]) - 1) / 2) * width)
                heights.append(rates[key][group])
        drawn = bars(axis, xs, heights, width, label + ("" if validated else " [unvalidated]"),
                     styles(label)[0], validated)
        axis.bar_label(drawn, labels=[f"{h:.3g}" for h in heights], fontsize=6, padding=1,
                       rotation=90)
    for goal in targets(ctx.registry, suite, STEPS_PER_SECOND, "moving_boxes"):
        axis.axhline(goal.value, color="red", linestyle="--", linewidth=1.0,
                     label=target_text(goal, f"{goal.value:g} steps/s at n={format_n(goal.n)}"))
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
    legend_below(axis, bbox_to_anchor=(0.5, -0.14), ncol=4)
    finish_figure(figure, "collide: steps per second on moving boxes (higher is better)")
    return [save_atomically(figure, os.path.join(ctx.out_dir, MOVING_FILE),
                            rows=workload_rows(ctx, "moving_boxes", stepped=False))]


def refit_decay_series(rows, include_unvalidated):
    """{(n, params without step): {metric: {(label, validated): {step: median}}}} of the
    moving_boxes per-step rows (params with step=K), metrics quality and time (ms).  Quality
    is a property of the tree, not a timing: it is drawn whatever its validated flag."""
    stepped = [row for row in rows if row.workload == "moving_boxes"
               and STEP_PARAM in dict(parse_params(row.params))]
    timing = select_timing(stepped, include_unvalidated, "collide per-step timing", metric=TIME)
    quality = [row for row in stepped if row.metric == "quality"]
    out = collections.defaultdict(lambda: collections.defaultdict(
        lambda: collections.defaultdict(lambda: collections.defaultdict(list))))
    for row in timing + quality:
        try:
            step = int(float(dict(parse_params(row.params))[STEP_PARAM]))
        except ValueError:
            continue
        if row.metric == TIME and row.unit not in UNIT_SECONDS:
            continue
        value = convert(row.value, row.unit, "ms") if row.metric == TIME else row.value
        out[(row.n, without_params(row.params, (STEP_PARAM,)))][row.metric][
            (label_of(row), row.validated)][step].append(value)
    return {group: {metric: median_points(series) for metric, series in metrics.items()}
            for group, metrics in out.items()}


def plot_collide_refit_decay(ctx, styles):
    data = refit_decay_series(ctx.rows, ctx.include_unvalidated)
    if not data:
        note(f"skip {DECAY_FILE}: no per-step ({STEP_PARAM}=K) collide rows of "
             f"workload moving_boxes")
        return []
    groups = sorted(data)
    entries = max(len(series) for metrics in data.values() for series in metrics.values())
    figure, axes = plt.subplots(len(groups), 2, squeeze=False,
                                figsize=(13, (4.2 + legend_inches(entries)) * len(groups) + 0.6))
    panels = (("quality", "quality: SAH node-area sum / root area (ratio)", "tree quality"),
              (TIME, "update + all pairs time (ms)", "time per step"))
    for row_axes, (n, params) in zip(axes, groups):
        for axis, (metric, ylabel, what) in zip(row_axes, panels):
            series = data[(n, params)].get(metric, {})
            title = f"n={format_n(n)} ({params}): {what}" if params else f"n={format_n(n)}: {what}"
            if not series:
                empty_panel(axis, f"{title}\nno {metric} rows")
                continue
            values = []
            for (label, validated), points in sorted(series.items(), key=validated_first):
                steps = sorted(points)
                values += [points[s] for s in steps]
                plot_series(axis, steps, [points[s] for s in steps], label, validated, styles,
                            markersize=4, label=label + ("" if validated else " [unvalidated]"))
            positive = [v for v in values if v > 0]
            if metric == TIME and positive and max(positive) / min(positive) > 10:
                axis.set_yscale("log")  # rebuild spikes would flatten the rest
            axis.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
            axis.set_xlabel("step")
            axis.set_ylabel(ylabel)
            axis.set_title(title, fontsize="medium")
            axis.grid(True, which="major", alpha=0.5)
            legend_below(axis)
    finish_figure(figure, "collide: BVH update strategies on moving boxes, step by step "
                          "(a refitted tree ages: its quality ratio grows)")
    return [save_atomically(figure, os.path.join(ctx.out_dir, DECAY_FILE),
                            rows=workload_rows(ctx, "moving_boxes", stepped=True))]


def collide_bv_points(rows, registry, include_unvalidated):
    """{(params, n): [(label, candidate pairs, false-positive ratio, exact-pairs time (s),
    build time (s))]} of workload triangles, one point per (structure, bv); nan where a figure
    is missing (times follow the validation rule, pair counts and ratios do not)."""
    triangles = [row for row in rows if row.workload == "triangles"]
    timing = select_timing(triangles, include_unvalidated, "collide triangles timing",
                           metric=TIME, operation=("build", "exact_pairs"))
    counts = [row for row in triangles if row.operation == "candidate_pairs"
              and row.metric in ("pairs", "false_positive_ratio")]
    cells = collections.defaultdict(lambda: collections.defaultdict(list))
    for row in timing + counts:
        if row.metric == TIME and row.unit not in UNIT_SECONDS:
            continue
        value = convert(row.value, row.unit, "s") if row.metric == TIME else row.value
        label = row.bv if row.bv and registry.bv(row.structure) == row.bv else label_of(row)
        if row.metric == TIME and not row.validated:
            label += " [unvalidated]"
        cells[(row.params, row.n, label)][(row.operation, row.metric)].append(value)
    out = collections.defaultdict(list)
    for (params, n, label), metrics in sorted(cells.items()):
        def get(operation, metric):
            values = metrics.get((operation, metric))
            return median(values) if values else float("nan")
        out[(params, n)].append((label, get("candidate_pairs", "pairs"),
                                 get("candidate_pairs", "false_positive_ratio"),
                                 get("exact_pairs", TIME), get("build", TIME)))
    return dict(out)


def plot_collide_bv_tradeoff(ctx):
    data = collide_bv_points(ctx.rows, ctx.registry, ctx.include_unvalidated)
    groups = [g for g in sorted(data) if any(p[1] > 0 for p in data[g])]
    if not groups:
        note(f"skip {BV_FILE}: no collide rows of workload triangles with candidate pairs")
        return []
    figure, axes = plt.subplots(len(groups), 2, squeeze=False, figsize=(14, 6 * len(groups)))
    for row_axes, (params, n) in zip(axes, groups):
        where = f"{params} n={format_n(n)}" if params else f"n={format_n(n)}"
        for axis, index, what in ((row_axes[0], 0, "exact-pairs time"),
                                  (row_axes[1], 1, "build time")):
            drawn = [(label + (f" (fp {fp:.2f})" if math.isfinite(fp) else ""), candidates,
                      times[index])
                     for label, candidates, fp, *times in data[(params, n)]
                     if candidates > 0 and math.isfinite(times[index]) and times[index] > 0]
            if not drawn:
                empty_panel(axis, f"{where}: no {what} rows")
                continue
            draw_tradeoff_panel(axis, drawn, "candidate pairs (BV overlaps reaching the exact "
                                             "test; fp = false-positive ratio)",
                                f"{what} (s)", f"triangles {where}: {what} against candidate pairs")
    figure.suptitle("collide: what bounding-volume accuracy costs in time (triangle soup self-"
                    "intersection; one point per BVH volume type; lower-left is better)")
    figure.tight_layout(rect=(0, 0, 1, 1.0 - 0.5 / figure.get_figheight()))
    return [save_atomically(figure, os.path.join(ctx.out_dir, BV_FILE),
                            rows=workload_rows(ctx, "triangles"))]


def workload_rows(ctx, workload, stepped=None):
    """The rows a figure of one workload draws (its run caption): validated ones unless
    unvalidated rows are drawn; stepped=True/False keeps only the rows with/without step=K."""
    return [row for row in ctx.rows if row.workload == workload
            and (row.validated or ctx.include_unvalidated)
            and (stepped is None or (STEP_PARAM in dict(parse_params(row.params))) == stepped)]


@figure_family("collide", suites=(SUITE,), exclusive=True, order=70)
def draw(ctx):
    """The collide suite's four figures; notes (no crash) for workloads it lacks."""
    # The structures a target is about are drawn black with stars in every collide figure.
    entry = ctx.registry.suite(SUITE)
    styles = ctx.styles.emphasised({t.structure for t in entry.targets if t.structure})
    return (plot_collide_boxes(ctx, SUITE, styles) + plot_collide_moving(ctx, SUITE, styles)
            + plot_collide_refit_decay(ctx, styles) + plot_collide_bv_tradeoff(ctx))
