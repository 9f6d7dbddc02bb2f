"""Reading: the tidy results tables (results/*.csv) and the registry (results/registry.json).

A table has the columns
    suite,structure,bv,workload,n,dim,scalar,operation,params,metric,value,unit,validated,run_id
(extra columns after them are ignored, except `check`, which is kept when present: a row whose
`check` is `none` was covered by no check and counts as unvalidated, whatever its `validated`
says; a `bv` of "-" means none, like an empty one).  Files that
are empty, lack these columns or hold malformed rows are skipped with a note on stderr; so are
rows whose suite or structure the registry does not list.  The registry is required: without a
usable one read_registry raises RegistryError naming the file.
"""

import collections
import csv
import json
import math
import os
import sys

from .registry import Registry, RegistryError

# The columns that name a figure: one row per key across a results folder's tables.
KEY_COLUMNS = ("suite", "structure", "bv", "workload", "n", "dim", "scalar", "operation", "params", "metric")
REQUIRED_COLUMNS = KEY_COLUMNS + ("value", "unit", "validated", "run_id")
REGISTRY_FILE = "registry.json"

OPTIONAL_COLUMNS = ("check",)  # kept when the table has them, "" otherwise
UNCHECKED = "none"  # the check column's word for "no check covered this figure"

Row = collections.namedtuple("Row", REQUIRED_COLUMNS + OPTIONAL_COLUMNS,
                             defaults=("",) * len(OPTIONAL_COLUMNS))


def note(message):
    """A skipped input or plot: goes to stderr so stdout lists only the PNGs written."""
    print("plot_results: " + message, file=sys.stderr)


def _parse_bool(text):
    return text.strip().lower() in ("true", "1", "yes")


def read_registry(path):
    """The Registry in `path`; RegistryError (naming the file) if it is missing or malformed."""
    try:
        with open(path, encoding="utf-8") as handle:
            data = json.load(handle)
    except FileNotFoundError:
        raise RegistryError(f"{path}: no such file (spatialbench writes it next to the CSV "
                            f"tables on every run; `spatialbench list --json` prints it)") from None
    except (OSError, UnicodeDecodeError) as error:
        raise RegistryError(f"{path}: cannot read ({error})") from None
    except json.JSONDecodeError as error:
        raise RegistryError(f"{path}: not valid JSON ({error})") from None
    return Registry.from_dict(data, source=path)


def read_csv_file(path):
    """Rows of one results CSV; [] (with a note) if the file is unusable."""
    try:
        if os.path.getsize(path) == 0:
            note(f"skip {path}: empty file")
            return []
        with open(path, newline="", encoding="utf-8-sig") as handle:
            lines = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as error:
        note(f"skip {path}: cannot read ({error})")
        return []

    lines = [line for line in lines if any(cell.strip() for cell in line)]
    if not lines:
        note(f"skip {path}: empty file")
        return []
    header = [cell.strip() for cell in lines[0]]
    missing = [name for name in REQUIRED_COLUMNS if name not in header]
    if missing:
        note(f"skip {path}: header lacks column(s) {', '.join(missing)}")
        return []
    index = {name: header.index(name) for name in REQUIRED_COLUMNS}
    last_index = max(index.values())
    index.update({name: header.index(name) for name in OPTIONAL_COLUMNS if name in header})

    rows, bad = [], 0
    for line in lines[1:]:
        if len(line) <= last_index:
            bad += 1
            continue
        cells = {name: line[i].strip() if i < len(line) else "" for name, i in index.items()}
        if cells["suite"] == "suite":  # a repeated header from concatenated files
            continue
        try:
            cells["n"] = int(float(cells["n"]))
            cells["dim"] = int(float(cells["dim"]))
            cells["value"] = float(cells["value"])
        except ValueError:
            bad += 1
            continue
        if not math.isfinite(cells["value"]):
            bad += 1
            continue
        cells["validated"] = (_parse_bool(cells["validated"])
                              and cells.get("check", "") != UNCHECKED)
        if cells["bv"] == "-":  # the collide and scenes suites write "-" for "no volume type"
            cells["bv"] = ""
        rows.append(Row(**cells))
    if bad:
        note(f"{path}: skipped {bad} malformed row(s)")
    if not rows:
        note(f"skip {path}: no data rows")
    return rows


def known_rows(rows, registry, table):
    """The rows whose suite and structure the registry lists; a note per unknown name."""
    suites = collections.Counter(row.suite for row in rows if registry.suite(row.suite) is None)
    for suite, count in sorted(suites.items()):
        note(f"skip suite '{suite or '<empty>'}' ({count} rows) in {table}: not in "
             f"{registry.source}")
    rows = [row for row in rows if registry.suite(row.suite) is not None]
    structures = collections.Counter(row.structure for row in rows
                                     if registry.structure(row.structure) is None)
    for structure, count in sorted(structures.items()):
        note(f"skip structure '{structure or '<empty>'}' ({count} rows) in {table}: not in "
             f"{registry.source}")
    return [row for row in rows if registry.structure(row.structure) is not None]


def tuning_rows(rows, registry):
    """Split rows into (curve rows, tuning rows).  A tuning row measures a configuration of a
    tuning sweep (its params name one of its structure's registry settings, e.g.
    `k=10;bucket_size=32`) or names the run's fastest peer configuration (best_peer_ratio): one
    size, one case each, which the complexity curves and summaries leave out (the tables and
    the paper's best-peer table report them)."""
    curves, tuning = [], []
    for row in rows:
        settings = registry.settings(row.structure)
        named = {item.split("=", 1)[0] for item in row.params.split(";") if item}
        (tuning if row.metric == "best_peer_ratio" or named & set(settings) else curves).append(row)
    return curves, tuning


def table_names(results_dir):
    """Sorted *.csv names in results_dir; None (with a note) when there is nothing to plot."""
    if not os.path.isdir(results_dir):
        note(f"no results directory {results_dir}: nothing to plot")
        return None
    names = sorted(name for name in os.listdir(results_dir) if name.endswith(".csv"))
    if not names:
        note(f"no *.csv in {results_dir}: nothing to plot")
        return None
    return names


def read_results(results_dir, registry, names=None):
    """All usable rows of results_dir/*.csv whose suite and structure are in the registry,
    without the tuning-sweep rows (tuning_rows)."""
    if names is None:
        names = table_names(results_dir) or []
    rows = []
    for name in names:
        curves, tuning = tuning_rows(known_rows(read_csv_file(os.path.join(results_dir, name)), registry, name),
                                     registry)
        if tuning:
            note(f"{name}: {len(tuning)} tuning-sweep row(s) kept out of the curves")
        rows.extend(curves)
    return rows


__all__ = ["REQUIRED_COLUMNS", "REGISTRY_FILE", "Row", "RegistryError", "note", "read_registry",
           "read_csv_file", "known_rows", "tuning_rows", "table_names", "read_results"]
