"""Cross-workload summaries: <suite>_summary.png, one picture per suite that ranks the
structures over all of the suite's workloads.

For the suite's headline measurement (SUMMARIES: knn and structures: exact kNN, k = 10 and
k = 1, time per query; raycast: incoherent rays, time per ray; collide: all pairs of static
boxes (build + pairs) and of moving boxes (update + pairs, per step); scenes: steps per second;
bv: the BVH built over each volume type, time per incoherent ray and time of all exact triangle
pairs), every case (a workload with its dim, scalar and params; collide: also each n, since it
has one workload per kind) is reduced to one number per structure, and each structure's number
is divided by the best structure's in that case: 1 is the fastest, 2 takes twice its time
(for rates, best rate / rate).

* Rows: validated ones only (`validated` true and `check` not `none`), whatever
  --include-unvalidated says: a ranking mixes nothing unchecked.  Repeated runs of one key
  (same structure, case and n, different run_id) are pooled by their median first.
* n: a case is compared at its largest n.  A structure not measured there (brute force and
  slow peers stop early) is compared with the best structure at its own largest n among those
  where at least two structures were measured; such points are drawn hollow.
* Drawing: one row per structure (names and colours as in every figure), sorted by the median
  of its ratios (best at the top); every case's ratio is a point (marker by headline variant,
  e.g. k = 10 against k = 1), the median a black bar with its value, the min-max spread a line;
  log x axis, a dashed line at 1.
"""

import collections
import os
import textwrap
from dataclasses import dataclass
from typing import Callable, Optional, Tuple

import matplotlib.lines as lines
import matplotlib.pyplot as plt
import matplotlib.transforms as transforms
import numpy as np

from ..core import STEPS_PER_SECOND, TIME, UNIT_SECONDS, label_of, median, parse_params
from ..family import figure_family
from ..figures import legend_below, save_atomically
from ..io import note

SUMMARY_FILE = "{suite}_summary.png"
ROW_INCHES = 0.28
WIDTH_INCHES = 9.5
VARIANT_MARKERS = "o^sDv<>P"
JITTER = 0.22  # vertical spread of a row's points, in rows
TITLE_CHARACTERS = 95  # the title's lines are wrapped at this width
LEGEND_DROP_POINTS = 34  # the variant legend sits this far below the axes (under the x label)


@dataclass(frozen=True)
class Headline:
    """One measurement a summary ranks by: the rows of `suite` with this operation and metric
    whose params are one of `params` (any when empty; never a per-step row `step=K`)."""
    suite: str
    operation: str
    metric: str
    params: Tuple[str, ...] = ()
    workloads: Tuple[str, ...] = ()  # any when empty
    higher_is_better: bool = False
    every_n: bool = False  # each n is a case of its own (suites with a single workload)
    variant: str = ""  # the legend name of this headline's points; "" -> its params


@dataclass(frozen=True)
class Summary:
    suite: str  # the file is <suite>_summary.png; the suite must have rows for it to be drawn
    what: str  # the title's description of the headline
    headlines: Tuple[Headline, ...]
    # registry, structure -> whether it is ranked (None: every structure)
    keep: Optional[Callable] = None
    # registry, row -> the entry a row counts for (None: label_of, structure<bv>)
    entry: Optional[Callable] = None


def _bvh_over_volume(registry, structure):
    """A BVH built with binned SAH whose variants differ only in the node volume (not the
    motion strategies or the median builder)."""
    settings = registry.settings(structure)
    entry = registry.structure(structure)
    return (entry is not None and entry.family == "bvh" and settings.get("builder") == "sah"
            and "strategy" not in settings)


def _volume_type(registry, row):
    return row.bv or registry.bv(row.structure) or row.structure


def _knn(suite):
    return Summary(suite, "exact kNN, time per query (k = 10 and k = 1)",
                   (Headline(suite, "knn", "time_per_op", ("k=10",), variant="k=10"),
                    Headline(suite, "knn", "time_per_op", ("k=1",), variant="k=1")))


SUMMARIES = (
    _knn("knn"),
    _knn("structures"),
    Summary("raycast", "incoherent rays on meshes, time per ray",
            (Headline("raycast", "ray", "time_per_op", ("rays=incoherent",),
                      variant="incoherent rays"),)),
    Summary("collide", "all overlapping pairs: static boxes (build + pairs) and moving boxes "
                       "(update + pairs per step)",
            (Headline("collide", "build_and_self_pairs", TIME, workloads=("boxes",),
                      every_n=True, variant="static boxes"),
             Headline("collide", "update_and_self_pairs", TIME, workloads=("moving_boxes",),
                      every_n=True, variant="moving boxes"))),
    Summary("scenes", "steps per second of each scene",
            (Headline("scenes", "step", STEPS_PER_SECOND, higher_is_better=True,
                      variant="scene"),)),
    Summary("bv", "BVH (binned SAH) over each volume type: time per incoherent ray (raycast; "
                  "aabb is traversed in the 8-wide ray layout, the others binary) and time of "
                  "all exact triangle pairs (collide)",
            (Headline("raycast", "ray", "time_per_op", ("rays=incoherent",),
                      variant="rays (raycast)"),
             Headline("collide", "exact_pairs", TIME, workloads=("triangles",),
                      variant="triangle pairs (collide)")),
            keep=_bvh_over_volume, entry=_volume_type),
)
SUITES = tuple(sorted({h.suite for s in SUMMARIES for h in s.headlines}
                      | {s.suite for s in SUMMARIES}))


@dataclass(frozen=True)
class Point:
    """One case's ratio for one entry."""
    case: tuple  # (workload, dim, scalar, operation, params[, n])
    variant: str
    ratio: float
    n: int  # the n compared at
    below_largest: bool  # n is smaller than the case's largest


def usable(row):
    """Validated and covered by a check (io.py reads check=none as not validated)."""
    return row.validated and row.check != "none"


def _params_match(headline, params):
    if "step" in dict(parse_params(params)):
        return False
    return not headline.params or params in headline.params


def select_rows(rows, summary, registry):
    """(headline, row) of the usable, positive rows a summary ranks by."""
    picked = []
    for headline in summary.headlines:
        for row in rows:
            if (row.suite == headline.suite and row.operation == headline.operation
                    and row.metric == headline.metric and row.value > 0 and usable(row)
                    and (not headline.workloads or row.workload in headline.workloads)
                    and _params_match(headline, row.params)
                    and (row.metric != TIME or row.unit in UNIT_SECONDS)
                    and (summary.keep is None or summary.keep(registry, row.structure))):
                picked.append((headline, row))
    return picked


def pooled(picked, summary, registry):
    """{(headline, case): {n: {entry: median value}}}: repeated runs of a key pooled by their
    median (times converted to seconds, so several tables of one case compare)."""
    raw = collections.defaultdict(lambda: collections.defaultdict(
        lambda: collections.defaultdict(list)))
    for headline, row in picked:
        case = (row.workload, row.dim, row.scalar, row.operation, row.params)
        if headline.every_n:
            case += (row.n,)
        entry = summary.entry(registry, row) if summary.entry else label_of(row)
        value = row.value * UNIT_SECONDS[row.unit] if row.metric == TIME else row.value
        raw[(headline, case)][row.n][entry].append(value)
    return {key: {n: {entry: median(values) for entry, values in by_entry.items()}
                  for n, by_entry in by_n.items()}
            for key, by_n in raw.items()}


def ratios(pooled_values):
    """{entry: [Point]}: each entry's value over the best value in each case (best over
    value for rates), at the case's largest n, or for an entry not measured there at its own
    largest n where at least two entries were measured."""
    out = collections.defaultdict(list)
    for (headline, case), by_n in pooled_values.items():
        shared = {n: values for n, values in by_n.items() if len(values) >= 2}
        if not shared:
            continue
        largest = max(by_n)
        entries = {entry for values in shared.values() for entry in values}
        for entry in sorted(entries):
            n = max(n for n, values in shared.items() if entry in values)
            values = shared[n]
            if headline.higher_is_better:
                ratio = max(values.values()) / values[entry]
            else:
                ratio = values[entry] / min(values.values())
            variant = headline.variant or ",".join(headline.params) or headline.operation
            out[entry].append(Point(case, variant, ratio, n, n < largest))
    return dict(out)


def ranking(points):
    """Entries sorted by the median of their ratios (then by name): the best first."""
    return sorted(points, key=lambda entry: (median([p.ratio for p in points[entry]]), entry))


def summarise(rows, summary, registry):
    """({entry: [Point]}, the rows used) of one summary."""
    picked = select_rows(rows, summary, registry)
    return ratios(pooled(picked, summary, registry)), [row for _, row in picked]


def _style_of(summary, registry, entry, picked_rows):
    """The label whose style an entry takes: itself, or (bv summary) the first registry
    structure of that volume type among the rows."""
    if summary.entry is None:
        return entry
    for name in registry.structures:
        for row in picked_rows:
            if row.structure == name and summary.entry(registry, row) == entry:
                return label_of(row)
    return entry


def draw_summary(axis, points, order, styles, style_of=lambda entry: entry):
    """One row per entry (order: top to bottom): the cases' ratios as points, the min-max
    spread as a line, the median as a black bar labelled with its value."""
    variants = sorted({p.variant for ps in points.values() for p in ps})
    markers = {v: VARIANT_MARKERS[i % len(VARIANT_MARKERS)] for i, v in enumerate(variants)}
    rng = np.random.default_rng(0)  # fixed jitter: the same picture on every run
    for y, entry in enumerate(order):
        colour, _ = styles(style_of(entry))
        values = [p.ratio for p in points[entry]]
        low, high, middle = min(values), max(values), median(values)
        axis.plot([low, high], [y, y], color=colour, linewidth=2.2, alpha=0.55, zorder=2,
                  solid_capstyle="butt")
        for point in points[entry]:
            offset = rng.uniform(-JITTER, JITTER)
            axis.scatter([point.ratio], [y + offset], marker=markers[point.variant], s=26,
                         facecolors="none" if point.below_largest else [colour],
                         edgecolors=[colour], linewidths=1.0, zorder=3)
        axis.plot([middle], [y], marker="|", markersize=16, markeredgewidth=2.6,
                  color="black", zorder=4)
        axis.annotate(f"{middle:.3g}\u00d7", (high, y), xytext=(8, 0),
                      textcoords="offset points", va="center", fontsize=8)
    axis.axvline(1.0, color="grey", linestyle="--", linewidth=1.0, zorder=1)
    axis.set_xscale("log")
    axis.set_yticks(range(len(order)))
    axis.set_yticklabels([f"{entry} ({len(points[entry])})" for entry in order])
    for tick, entry in zip(axis.get_yticklabels(), order):
        tick.set_color(styles(style_of(entry))[0])
    axis.set_ylim(len(order) - 0.5, -0.5)  # the best on top
    axis.grid(True, axis="x", which="major", alpha=0.5)
    axis.grid(True, axis="x", which="minor", alpha=0.15)
    right = max(p.ratio for ps in points.values() for p in ps)
    axis.set_xlim(0.8, right * 2.2)  # room for the median labels
    if len(variants) > 1:  # the markers' legend, in grey: colour is the structure
        handles = [lines.Line2D([], [], linestyle="none", marker=markers[v], color="dimgrey",
                                label=v) for v in variants]
        below = transforms.offset_copy(axis.transAxes, fig=axis.figure, y=-LEGEND_DROP_POINTS,
                                       units="points")
        legend_below(axis, handles=handles, bbox_to_anchor=(0.5, 0.0), bbox_transform=below,
                     ncol=min(4, len(variants)))


def _cases_text(points):
    cases = {(p.variant, p.case) for ps in points.values() for p in ps}
    workloads = {p.case[0] for ps in points.values() for p in ps}
    return f"{len(cases)} cases over {len(workloads)} workload(s)"


@figure_family("summary", suites=SUITES, order=90)
def draw(ctx):
    """Per suite, the structures ranked by their time relative to the best in each workload."""
    written = []
    for summary in SUMMARIES:
        if not any(row.suite == h.suite for h in summary.headlines for row in ctx.rows):
            continue
        points, used = summarise(ctx.rows, summary, ctx.registry)
        name = SUMMARY_FILE.format(suite=summary.suite)
        if len(points) < 2:
            note(f"skip {name}: fewer than two structures with validated "
                 f"{', '.join(sorted({h.operation for h in summary.headlines}))} rows to rank")
            continue
        order = ranking(points)
        figure, axis = plt.subplots(figsize=(WIDTH_INCHES, 1.9 + ROW_INCHES * len(order)))
        draw_summary(axis, points, order, ctx.styles,
                     lambda entry: _style_of(summary, ctx.registry, entry, used))
        measure = ("best rate / rate" if all(h.higher_is_better for h in summary.headlines)
                   else "time / best time")
        axis.set_xlabel(f"{measure} in the same case (1 = the best; log scale)")
        title = textwrap.fill(f"{summary.suite}: {summary.what}", TITLE_CHARACTERS)
        title += (f"\n{_cases_text(points)}, cases per structure in brackets; repeated runs "
                  f"pooled by median\npoints: cases at their largest n (hollow: a smaller n); "
                  f"black bar: median; line: min\u2013max")
        axis.set_title(title, fontsize="medium")
        figure.tight_layout()
        written.append(save_atomically(figure, os.path.join(ctx.out_dir, name), rows=used))
    return written

