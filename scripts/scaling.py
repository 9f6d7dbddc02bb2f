#!/usr/bin/python3
"""Fitted cost exponents and memory per object at the largest size: results/scaling.md.

For every figure measured at three or more sizes n (the same suite, structure, volume,
workload, dimension, scalar, operation, parameters and metric, from any table in the results
folder), the exponent b of value ~ a * n^b, fitted by least squares on log value against
log n over all sizes, and the local exponent between the two largest sizes (the slope of the
last decade, where caches and memory set the cost). Times: `build_time` and `fit_time` (a
whole build or fit, ideally b ~ 1 for O(n log n)), `time_per_op` (one query or update,
ideally b ~ 0 for O(log n)) and the collide suite's `time` (one whole pair query). Memory: `bytes_per_point` / `bytes_per_triangle` at the largest n, and the collide suite's
`memory` (the whole structure's bytes) divided by n.

Only validated rows (`validated` true, `check` not `none`) count. Only figures whose largest
size is in the decade of the largest size of their suite in the folder are listed (the scale
the tables reach; the same power of ten when rounded, since a generated mesh has about, not
exactly, its nominal size: the sphere of 1e7 has 9,991,920 triangles), so a table run at
1e7 decides what is shown; each section says that size.

    scripts/scaling.py [--results DIR] [--output FILE]   # default results/, DIR/scaling.md

Exit 1 with a message when the folder has no usable registry.json (written by every run).
"""

import argparse
import math
import os
import pathlib
import sys
from collections import defaultdict

# The tables are read, and exponents fitted, by the plots' package: one reader, one validation
# rule (a row counts when `validated` is true and its `check` is not `none`), one fit.
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "plots"))
from spatialplots.core import fit_exponent, format_n  # noqa: E402
from spatialplots.io import REGISTRY_FILE, RegistryError, read_registry, read_results  # noqa: E402

TIME_METRICS = ("build_time", "fit_time", "time_per_op", "time")
MEMORY_METRICS = ("bytes_per_point", "bytes_per_triangle")
# Whole-structure bytes (the collide suite's `memory`), listed per object: value / n.
TOTAL_MEMORY_METRICS = ("memory",)
KEY_FIELDS = ("suite", "structure", "bv", "workload", "dim", "scalar", "operation", "params", "metric")
MIN_SIZES = 3


def collect(results):
    """key -> {n: value} over the validated rows of every table (the tuning sweeps' rows are
    left out, as in the plots: the default configurations' curves)."""
    registry = read_registry(os.path.join(results, REGISTRY_FILE))
    figures = defaultdict(dict)
    for row in read_results(str(results), registry):
        if not row.validated or row.value <= 0 or row.metric not in TIME_METRICS + MEMORY_METRICS + TOTAL_MEMORY_METRICS:
            continue
        figures[tuple(str(getattr(row, f)) for f in KEY_FIELDS)].setdefault(row.n, row.value)
    return figures


def decade(n):
    """The power of ten n rounds to on a log scale: 9,991,920 and 10,000,000 are both 7."""
    return round(math.log10(n))


def at_largest(figures, largest, suite, metrics):
    """(key, display name, {n: value}) of the suite's figures in `metrics` whose largest size is
    in the decade of the suite's largest, in key order."""
    for key in sorted(figures):
        sizes = figures[key]
        if key[0] == suite and key[-1] in metrics and decade(max(sizes)) == decade(largest[suite]):
            structure, bv = key[1], key[2]
            yield key, structure + (f" ({bv})" if bv else ""), sizes


def exponent_lines(figures, largest, suite):
    lines = []
    for key, name, sizes in at_largest(figures, largest, suite, TIME_METRICS):
        _, _, _, workload, dim, scalar, operation, params, metric = key
        if len(sizes) < MIN_SIZES:
            continue
        ns, values = zip(*sorted(sizes.items()))
        last = math.log(values[-1] / values[-2]) / math.log(ns[-1] / ns[-2])
        lines.append(f"| {suite} | {name} | {workload} {dim}d {scalar} | {operation} | {params or '—'} | {metric} "
                     f"| {format_n(ns[0])} – {format_n(ns[-1])} ({len(ns)}) | {fit_exponent(ns, values):.2f} | {last:.2f} |")
    return lines


def memory_lines(figures, largest, suite):
    lines = []
    for key, name, sizes in at_largest(figures, largest, suite, MEMORY_METRICS + TOTAL_MEMORY_METRICS):
        _, _, _, workload, dim, scalar, _, params, metric = key
        n = max(sizes)
        per_object = sizes[n] / n if metric in TOTAL_MEMORY_METRICS else sizes[n]
        shown = f"{metric} ÷ n" if metric in TOTAL_MEMORY_METRICS else metric
        lines.append(f"| {suite} | {name} | {workload} {dim}d {scalar} | {params or '—'} | {shown} | {format_n(n)} | {per_object:.1f} |")
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", default="results", type=pathlib.Path)
    parser.add_argument("--output", type=pathlib.Path)
    args = parser.parse_args()
    output = args.output or args.results / "scaling.md"
    try:
        figures = collect(args.results)
    except RegistryError as e:
        print(f"scaling: {e}", file=sys.stderr)
        return 1
    largest = defaultdict(int)
    for key, sizes in figures.items():
        largest[key[0]] = max(largest[key[0]], max(sizes))
    out = ["# Cost exponents and memory at the largest size", "",
           "Generated by `scripts/scaling.py` from the validated rows of the tables in this folder; the main",
           "job rewrites it. Do not edit. b: the exponent of value ~ a·n^b, least squares on logs over every",
           "size; last decade: the slope between the two largest sizes. `build_time` and `fit_time` are a whole",
           "build or fit (O(n log n) gives b a little above 1), `time_per_op` one query or update (O(log n)",
           "gives b near 0), `time` (collide) one whole pair query. n is the suite's size: points, triangles,",
           "boxes; in the bv suite's overlap and ray rows, points per instance.",
           "Only figures that reach the decade of their suite's largest size in these tables are listed (a",
           "generated mesh has about its nominal size: n is its own). The sizes of one",
           "figure may come from different runs (provenance.md): an exponent then compares absolute times",
           "across runs on a shared machine, whose single figures swing by 10-20 %, so its second decimal",
           "is noise.", ""]
    for suite in sorted(largest):
        out += [f"## {suite}: largest size {format_n(largest[suite])}", "",
                "| suite | structure | workload | operation | params | metric | sizes (count) | b | last decade |",
                "|---|---|---|---|---|---|---|---|---|"]
        out += exponent_lines(figures, largest, suite) or ["| (none at three or more sizes) ||||||||"]
        out += ["", "| suite | structure | workload | params | metric | n | bytes per object |", "|---|---|---|---|---|---|---|"]
        out += memory_lines(figures, largest, suite) or ["| (none) ||||||"]
        out.append("")
    output.write_text("\n".join(out))
    print(f"scaling: wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
