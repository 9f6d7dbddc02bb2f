#!/usr/bin/python3
"""Check that result tables keep their keys and their answers across a change.

A refactoring of the harness must not change what the suites measure: every key of a
reference run (suite, structure, bv, workload, n, dim, scalar, operation, params, metric)
must appear again, and every ANSWER figure of our own structures (pair counts, hits, recall,
tightness, nodes visited, ...) must be the same number. Timings, memory and the peers'
figures (whose answers can depend on the CPU their library dispatches to) are compared by key
only. New keys are allowed only for the structures named with --allow-new.

    check_table_keys.py --write REFERENCE.csv TABLE.csv ...     # record a reference
    check_table_keys.py REFERENCE.csv TABLE.csv ... [--allow-new NAME ...]

Exit 0 when everything holds; 1 with one line per problem (at most 20) otherwise.
"""

import argparse
import csv
import math
import sys

KEY = ("suite", "structure", "bv", "workload", "n", "dim", "scalar", "operation", "params", "metric")
# Figures that are answers (deterministic for a given seed), not measurements of time or memory.
ANSWER_METRICS = {
    "recall", "hits", "rays", "ambiguous_rays", "volume", "tightness", "false_positive_rate_shapes",
    "positive_rate", "false_positive_rate_exact", "hit_rate", "pairs", "pairs_changed_per_step",
    "pairs_changed", "false_positive_ratio", "ray_hits", "range_results", "quality", "node_area_ratio",
    "nodes_visited",
}
# Figures whose structure and params name what the run selected (the fastest peer
# configuration: best_peer_ratio), so that their keys are compared as counts per figure.
SELECTED_METRICS = {"best_peer_ratio"}
# Structures whose answers are compared by value: ours (the peers' are compared by key).
PEER_PREFIXES = ("nanoflann", "cgal", "embree", "fcl", "boost")
# Operations that run each peer at the configuration the run found fastest (the knn suite's
# batched kNN): a peer's row keeps the operation's own params (these names) and drops the
# selected configuration's settings, which timing noise may change between runs.
SELECTED_CONFIGURATION = {"knn_batch": ("k", "order", "threads")}


def read_rows(paths):
    rows = {}
    selected = {}
    for path in paths:
        with open(path, newline="") as f:
            for line, row in enumerate(csv.DictReader(f), start=2):
                missing = [k for k in KEY + ("value",) if k not in row]
                if missing:
                    raise SystemExit(f"{path}:{line}: missing column(s) {', '.join(missing)}")
                key = tuple(row[k] for k in KEY)
                own = SELECTED_CONFIGURATION.get(row["operation"])
                if own and row["structure"].startswith(PEER_PREFIXES):
                    params = ";".join(p for p in row["params"].split(";") if p.split("=")[0] in own)
                    key = key[:8] + (params,) + key[9:]
                if row["metric"] in SELECTED_METRICS:
                    # The row names the configuration a run selected, which timing noise may
                    # change: kept as "one more such row of this figure", numbered.
                    base = key[:1] + ("",) + key[2:8] + ("",) + key[9:]
                    selected[base] = selected.get(base, 0) + 1
                    key = base[:8] + (f"#{selected[base]}",) + base[9:]
                rows.setdefault(key, row["value"])  # repeated runs of a key: the first
    return rows


def compared_by_value(key):
    suite, structure, metric = key[0], key[1], key[9]
    # Ray nodes visited count wide nodes, whose width follows the CPU (8 lanes with AVX, else 4).
    if suite == "raycast" and metric == "nodes_visited":
        return False
    return metric in ANSWER_METRICS and not structure.startswith(PEER_PREFIXES)


def same(a, b):
    x, y = float(a), float(b)
    return x == y or (math.isfinite(x) and math.isfinite(y) and abs(x - y) <= 1e-9 * max(abs(x), abs(y)))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--write", action="store_true", help="write the reference instead of checking")
    parser.add_argument("reference")
    parser.add_argument("tables", nargs="+")
    parser.add_argument("--allow-new", nargs="*", default=[], help="structures that may add keys")
    args = parser.parse_args(argv)

    new = read_rows(args.tables)
    if args.write:
        with open(args.reference, "w", newline="") as f:
            out = csv.writer(f, lineterminator="\n")
            out.writerow(KEY + ("value",))
            for key in sorted(new):
                out.writerow(key + ((new[key] if compared_by_value(key) else ""),))
        print(f"check_table_keys: wrote {len(new)} keys to {args.reference}")
        return 0

    reference = read_rows([args.reference])
    problems = []
    for key, value in sorted(reference.items()):
        where = ",".join(key)
        if key not in new:
            problems.append(f"missing key: {where}")
        elif value != "" and not same(value, new[key]):
            problems.append(f"changed answer: {where}: {value} -> {new[key]}")
    for key in sorted(set(new) - set(reference)):
        if key[1] not in args.allow_new:
            problems.append(f"new key of a structure not allowed to add any: {','.join(key)}")
    for p in problems[:20]:
        print(p)
    if len(problems) > 20:
        print(f"... and {len(problems) - 20} more")
    compared = sum(1 for v in reference.values() if v != "")
    print(f"check_table_keys: {len(reference)} reference keys, {compared} answers compared by value, "
          f"{len(set(new) - set(reference))} new keys, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
