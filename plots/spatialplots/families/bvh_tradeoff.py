"""BVH accuracy against time: bvh_tradeoff.png (raycast suite), one row of panels per workload.

1. node tightness against build time: tightness is the sum over nodes of the volume's surface
   area divided by the same sum for the node AABBs (node_area_ratio: 1 for aabb, lower is
   tighter), one point per volume type at the n where the most volume types were measured
   (the largest such n);
2. the same tightness against time per incoherent ray;
3. the builders against each other: build time against ray time, one point per n, one line
   per builder.
Panels 1 and 2 star the Pareto front.  Which structures are which comes from the registry:
the lines of panel 3 are the structures with a `builder` setting that differ from another one
only in the builder (same `bv`, same other settings: bvh and bvh_median), labelled by the
builder ("sah" drawn "SAH"); the points of panels 1-2 are the structures with node_area_ratio
rows built by REFERENCE_BUILDER (or with no builder setting), labelled by their volume type.
"""

import itertools
import os

import matplotlib.pyplot as plt

from ..core import TIME_METRICS, convert, format_n, parse_params, workload_sort_key
from ..family import figure_family
from ..figures import draw_tradeoff_panel, empty_panel, save_atomically

BVH_TRADEOFF_FILE = "bvh_tradeoff.png"
REFERENCE_BUILDER = "sah"  # the builder the volume types are compared under (panels 1-2)
BUILDER_LABELS = {"sah": "SAH"}  # presentation of settings.builder values; others as written
BUILDER_MARKERS = "osD^v"


def builder_label(registry, structure):
    """settings.builder as drawn ("sah" -> "SAH"), None for a structure without one."""
    builder = registry.settings(structure).get("builder")
    return None if builder is None else BUILDER_LABELS.get(builder, builder)


def builder_groups(registry, structures):
    """{structure: label} of the structures panel 3 compares: those with a builder setting
    whose volume type and other settings equal those of a structure with another builder
    (bvh and bvh_median, not bvh_obb).  The label gets the other settings when several such
    groups are present."""
    groups = {}
    for structure in sorted(structures):
        settings = registry.settings(structure)
        if "builder" in settings:
            rest = tuple(sorted((k, v) for k, v in settings.items() if k != "builder"))
            groups.setdefault((registry.bv(structure), rest), []).append(structure)
    groups = {key: members for key, members in groups.items()
              if len({registry.settings(m)["builder"] for m in members}) > 1}
    out = {}
    for (_, rest), members in groups.items():
        for structure in members:
            label = builder_label(registry, structure)
            if len(groups) > 1 and rest:
                label += " (" + ",".join(f"{k}={v}" for k, v in rest) + ")"
            out[structure] = label
    return out


def bvh_tradeoff_points(rows, registry, include_unvalidated):
    """{workload: {"n": n, "points": [(bv, area_ratio, build_s, ray_ns)], "builders": [(label,
    n, build_s, ray_ns)]}}: per workload the n at which the most structures have a
    node_area_ratio row (the largest such n); incoherent rays."""
    rows = [row for row in rows if row.validated or include_unvalidated
            or row.metric not in TIME_METRICS]
    value = {}
    for row in rows:
        if row.operation == "build" and row.metric in ("build_time", "node_area_ratio"):
            value[(row.structure, row.bv, row.workload, row.n, row.metric)] = row.value
        elif (row.operation == "ray" and row.metric == "time_per_op"
              and dict(parse_params(row.params)).get("rays") == "incoherent"):
            value[(row.structure, row.bv, row.workload, row.n, "ray")] = convert(row.value, row.unit, "ns")
    builders = builder_groups(registry, {key[0] for key in value})
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
                if w != workload or m != n or metric != "node_area_ratio" or registry.settings(
                        structure).get("builder", REFERENCE_BUILDER) != REFERENCE_BUILDER:
                    continue
                build = value.get((structure, bv, w, m, "build_time"))
                ray = value.get((structure, bv, w, m, "ray"))
                if build and ray:
                    entry["points"].append((bv or structure, ratio, build, ray))
        for (structure, bv, w, m, metric), build in sorted(value.items()):
            label = builders.get(structure)
            if w == workload and metric == "build_time" and label is not None:
                ray = value.get((structure, bv, w, m, "ray"))
                if ray:
                    entry["builders"].append((label, m, build, ray))
        if entry["points"] or entry["builders"]:
            out[workload] = entry
    return out


@figure_family("bvh_tradeoff", suites=("raycast",), order=60)
def draw(ctx):
    """Node tightness per volume type against build and ray time; builder against builder."""
    data = bvh_tradeoff_points(ctx.rows, ctx.registry, ctx.include_unvalidated)
    if not data:
        return []
    figure, axes = plt.subplots(len(data), 3, figsize=(19, 6 * len(data)), squeeze=False)
    tightness = "node tightness: sum area(BV) / sum area(AABB)"
    for row_axes, (workload, entry) in zip(axes, data.items()):
        points = entry["points"]
        if points:
            where = f"{workload} n={format_n(entry['n'])}"
            draw_tradeoff_panel(row_axes[0], [(label, b, r) for label, r, b, _ in points],
                                "build time (s)", tightness,
                                f"{where}: tightness against build time", log_y=False)
            draw_tradeoff_panel(row_axes[1], [(label, t, r) for label, r, _, t in points],
                                "time per incoherent ray (ns)", tightness,
                                f"{where}: tightness against ray time", log_y=False)
        else:
            for axis in row_axes[:2]:
                empty_panel(axis, f"{workload}: no node-tightness rows")
        axis = row_axes[2]
        reference = BUILDER_LABELS.get(REFERENCE_BUILDER, REFERENCE_BUILDER)
        labels = sorted({label for label, *_ in entry["builders"]},
                        key=lambda label: (not label.startswith(reference), label))
        for label, marker in zip(labels, itertools.cycle(BUILDER_MARKERS)):
            pts = sorted((n, b, r) for name, n, b, r in entry["builders"] if name == label)
            axis.plot([b for _, b, _ in pts], [r for _, _, r in pts], marker=marker, label=label)
            for n, b, r in pts:
                axis.annotate(format_n(n), (b, r), fontsize=7, xytext=(3, 3), textcoords="offset points")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("build time (s)")
        axis.set_ylabel("time per incoherent ray (ns)")
        axis.set_title(f"{workload}: " + " against ".join(labels[::-1] or ["builders"])
                       + " (aabb; labels: n)", fontsize="medium")
        axis.grid(True, which="both", alpha=0.3)
        if entry["builders"]:
            axis.legend(fontsize="small")
    figure.suptitle("bvh: what node tightness and the builder cost (raycast suite; lower-left is better)")
    figure.tight_layout(rect=(0, 0, 1, 0.985))
    return [save_atomically(figure, os.path.join(ctx.out_dir, BVH_TRADEOFF_FILE))]
