#!/usr/bin/python3
"""Takes out of a result table the rows whose key another table already holds.

results/README.md keeps a few side tables of figures measured by a dedicated run (for example
`knn_order_1e6.csv`, `knn_bulk_1e6.csv`) whose keys the suite's main table would repeat: the
main job's knn run measures the same operations at the same size again. Each key must have
one row across the tables of the folder (results/README.md), so after the main job's run the
main table's rows with those keys are taken out, the side tables' rows stay. The key is the
columns that name a figure: suite, structure, bv, workload, n, dim, scalar, operation, params,
metric. Nothing else is edited; the table's other rows keep their order.

    scripts/drop_keys_held_elsewhere.py TABLE SIDE_TABLE...

A side table that does not exist is skipped with a note (a fresh checkout's main job still
runs). Exit 1 with a message naming the file when a table lacks a key column.
"""

import csv
import pathlib
import sys

# The key columns are the plots' package's, as for scripts/scaling.py: one place names them.
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "plots"))
from spatialplots.io import KEY_COLUMNS as KEY  # noqa: E402


def key_columns(header, path):
    missing = [c for c in KEY if c not in header]
    if missing:
        raise ValueError(f"{path}: no column {', '.join(missing)} (a result table names each figure by {', '.join(KEY)})")
    return [header.index(c) for c in KEY]


def keys_of(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        return set()
    columns = key_columns(rows[0], path)
    return {tuple(row[i] for i in columns) for row in rows[1:] if row}


def main(argv):
    if len(argv) < 2:
        print("usage: drop_keys_held_elsewhere.py TABLE SIDE_TABLE...", file=sys.stderr)
        return 2
    table, sides = pathlib.Path(argv[0]), [pathlib.Path(p) for p in argv[1:]]
    try:
        held = set()
        for side in sides:
            if side.exists():
                held |= keys_of(side)
            else:
                print(f"drop_keys_held_elsewhere: {side}: no such table, skipped")
        with open(table, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
        if not rows:
            print(f"drop_keys_held_elsewhere: {table}: empty, nothing to do")
            return 0
        columns = key_columns(rows[0], table)
    except (OSError, ValueError) as error:
        print(f"drop_keys_held_elsewhere: {error}", file=sys.stderr)
        return 1
    kept = [rows[0]] + [row for row in rows[1:] if not row or tuple(row[i] for i in columns) not in held]
    dropped = len(rows) - len(kept)
    # Written to a temporary file and renamed: an interrupted run leaves the table whole.
    temporary = table.with_name(table.name + ".tmp")
    with open(temporary, "w", newline="", encoding="utf-8") as f:
        csv.writer(f, lineterminator="\n").writerows(kept)
    temporary.replace(table)
    print(f"drop_keys_held_elsewhere: {table}: {dropped} row(s) whose key {', '.join(str(s) for s in sides)} hold taken out")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
