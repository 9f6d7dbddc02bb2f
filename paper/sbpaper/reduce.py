"""The few ways a quoted number is computed from rows, named so that the provenance can say
which one was used and the read-back test can redo it.

A quote's rows come in groups; each group is one figure measured once or in several runs
(told apart by run_id), and is reduced to the median of its rows first.  The operation then
combines the group medians."""

import math
import statistics


def group_value(rows):
    return statistics.median(row.value for row in rows)


def exponent(ns, values):
    """Least-squares slope of log(value) against log(n): the value grows like n^slope."""
    xs = [math.log(n) for n in ns]
    ys = [math.log(v) for v in values]
    mean_x, mean_y = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mean_x) ** 2 for x in xs)
    return sum((x - mean_x) * (y - mean_y) for x, y in zip(xs, ys)) / sxx


OPERATIONS = {
    "value": lambda vs, ns: vs[0],
    "ratio": lambda vs, ns: vs[0] / vs[1],
    "min": lambda vs, ns: min(vs),
    "max": lambda vs, ns: max(vs),
    "sum": lambda vs, ns: sum(vs),
    "count": lambda vs, ns: len(vs),
    "mean": lambda vs, ns: sum(vs) / len(vs),
    "geomean": lambda vs, ns: math.exp(sum(math.log(v) for v in vs) / len(vs)),
    "share": lambda vs, ns: sum(vs[1:]) / vs[0],  # the parts over the whole (first group)
    "exponent": lambda vs, ns: exponent(ns, vs),
    "n": lambda vs, ns: ns[0],  # the problem size the rows were measured at
}


def compute(operation, groups):
    values = [group_value(group) for group in groups]
    ns = [group[0].n for group in groups]
    return OPERATIONS[operation](values, ns)
