"""Ratios: <suite>_ratios.png, drawn when a suite has time_ratio rows.

Bars of time(baseline) / time(peer), where the baseline is the suite's `baseline` in the
registry (kd_tree for knn and structures): one bar per peer for each (operation, params), one
subplot per (workload, dim, scalar).  Below 1 the baseline is faster.  Each peer is shown at the
largest n it was measured at (brute force often stops early); the legend says so when that n is
below the subplot's largest.  A grey dashed line marks 1.0; the y axis is logarithmic only when
the ratios span more than a decade.  A row names the peer in `structure`, or in a `vs=` /
`peer=` param (then `structure` is the baseline).
"""

import collections
import math
import os

import numpy as np

from ..core import format_n, format_params, label_of, median, parse_params, slug, \
    split_validated, workload_sort_key
from ..family import figure_family
from ..figures import bars, finish_figure, legend_below, new_figure, save_atomically
from ..io import note

RATIO_METRIC = "time_ratio"
PEER_PARAMS = ("vs", "peer")


def ratio_panels(rows, suite):
    """{(workload, dim, scalar): {peer: {(operation, params): {n: [ratios]}}}} of one suite."""
    panels = collections.defaultdict(lambda: collections.defaultdict(
        lambda: collections.defaultdict(lambda: collections.defaultdict(list))))
    for row in rows:
        if row.suite != suite:
            continue
        pairs = parse_params(row.params)
        named = dict(pairs)
        peer = next((named[k] for k in PEER_PARAMS if named.get(k)), None) or label_of(row)
        params = format_params([(k, v) for k, v in pairs if k not in PEER_PARAMS])
        if not row.validated:
            peer += " [unvalidated]"
        panels[(row.workload, row.dim, row.scalar)][peer][(row.operation, params)][row.n] \
            .append(row.value)
    return panels


@figure_family("ratios", order=40)
def draw(ctx):
    """Baseline time over peer time, per suite with time_ratio rows."""
    ratio_rows = [row for row in ctx.rows if row.metric == RATIO_METRIC and row.value > 0]
    ratio_rows = split_validated(ratio_rows, ctx.include_unvalidated, RATIO_METRIC)
    written = []
    for suite in sorted({row.suite for row in ratio_rows}):
        baseline = ctx.registry.baseline(suite)
        if not baseline:
            note(f"{suite}_ratios.png: suite '{suite}' has no baseline in "
                 f"{ctx.registry.source}; the ratios are labelled 'baseline'")
            baseline = "baseline"
        panels = ratio_panels(ratio_rows, suite)
        keys = sorted(panels, key=lambda k: (workload_sort_key(k[0]), k[1], k[2]))
        entries = max(len(panels[key]) for key in keys) + 1  # + the 1.0 line
        figure, axes = new_figure(len(keys), entries)
        for axis, key in zip(axes, keys):
            draw_ratio_panel(axis, key, panels[key], ctx.styles, baseline)
        finish_figure(figure, f"{suite}: {baseline} time / peer time "
                              f"(below 1: {baseline} faster)")
        written.append(save_atomically(
            figure, os.path.join(ctx.out_dir, f"{slug(suite)}_ratios.png"),
            rows=[row for row in ratio_rows if row.suite == suite]))
    return written


def draw_ratio_panel(axis, key, by_peer, styles, baseline):
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
        label = peer + (f" (n={format_n(n)})" if n != largest_n else "")
        drawn = bars(axis, positions + (i - (len(peers) - 1) / 2) * width, heights, width, label,
                     colour, validated=not peer.endswith("[unvalidated]"))
        axis.bar_label(drawn, fmt="%.3g", fontsize=6, padding=1)
    axis.axhline(1.0, color="grey", linestyle="--", linewidth=1.0, label="equal time (1.0)")
    if heights_seen and max(heights_seen) / min(heights_seen) > 10:
        axis.set_yscale("log")  # ratios spanning decades (brute force) hide each other linearly
    else:
        axis.set_ylim(0, max(heights_seen + [1.0]) * 1.12)  # room for the value labels
    axis.set_xticks(positions)
    axis.set_xticklabels([f"{op}\n{params}" if params else op for op, params in group_keys],
                         fontsize="small")
    axis.set_ylabel(f"{baseline} time / peer time (ratio)")
    axis.set_title(f"{workload}, n={format_n(largest_n)}, {dim}D, {scalar}")
    axis.grid(True, axis="y", alpha=0.5)
    legend_below(axis)
