"""Helpers of the plots tests: registry fixtures, CSV rows in a temporary directory, and
running the entry point with its output captured.  Nothing here touches results/ or plots/."""

import contextlib
import csv
import io
import json
import os
import sys
import tempfile
import unittest

PLOTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(PLOTS, "plot_results.py")
if PLOTS not in sys.path:  # when run other than by `unittest discover -t plots`
    sys.path.insert(0, PLOTS)

from spatialplots import cli  # noqa: E402
from spatialplots.io import read_registry, read_results  # noqa: E402

HEADER = ["suite", "structure", "bv", "workload", "n", "dim", "scalar", "operation", "params",
          "metric", "value", "unit", "validated", "run_id"]
NS = [1000, 10000, 100000, 1000000]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

# Complexity tables in the registry's form: a tree, a grid (linear box pairs) and a linear scan.
TREE = {"*": "log n", "build": "n log n", "insert_hinted": "1", "collide": "n log n",
        "build_and_self_pairs": "n log n", "fit": "n"}
GRID = dict(TREE, build_and_self_pairs="n")
SCAN = {"*": "n", "insert": "1", "insert_loop": "1", "insert_bulk": "1", "insert_hinted": "1",
        "collide": "n^2", "build_and_self_pairs": "n^2"}


def structure(name, family=None, kind="library", settings=None, complexity=None):
    return {"name": name, "family": family or name, "kind": kind, "library": "test",
            "settings": settings or {}, "description": f"test structure {name}",
            "complexity": dict(complexity or (SCAN if kind == "oracle" else TREE))}


def suite(name, baseline="", targets=(), **extra):
    entry = {"name": name, "table": f"{name}.csv", "description": f"test suite {name}",
             "baseline": baseline, "targets": list(targets)}
    entry.update(extra)
    return entry


def registry_dict(suites, structures):
    return {"schema_version": 1, "generator": "plots tests", "suites": list(suites),
            "structures": list(structures)}


def row(suite="knn", structure="kd_tree", workload="uniform", n=1000, operation="knn",
        params="k=10", metric="time_per_op", value=1.0, unit="ns", validated="true", bv=""):
    return [suite, structure, bv, workload, n, 3, "double", operation, params, metric,
            repr(value), unit, validated, "test-run"]


def write_csv(directory, name, rows, header=HEADER):
    with open(os.path.join(directory, name), "w", newline="") as handle:
        writer = csv.writer(handle)
        if header is not None:
            writer.writerow(header)
        writer.writerows(rows)


def write_registry(directory, data):
    with open(os.path.join(directory, "registry.json"), "w") as handle:
        json.dump(data, handle)


def run_main(*args, **options):
    """cli.main(args) with stdout and stderr captured: (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.main(list(args), **options)
    return code, out.getvalue(), err.getvalue()


def pngs(directory):
    return sorted(name for name in os.listdir(directory) if name.endswith(".png"))


class ResultsTestCase(unittest.TestCase):
    """A temporary results/ (with the class's REGISTRY written to it) and out/ directory."""

    REGISTRY = None  # a registry dict; None writes none

    def setUp(self):
        self._temp = tempfile.TemporaryDirectory()
        self.results = os.path.join(self._temp.name, "results")
        self.out = os.path.join(self._temp.name, "out")
        os.makedirs(self.results)
        if self.REGISTRY is not None:
            write_registry(self.results, self.REGISTRY)

    def tearDown(self):
        self._temp.cleanup()

    def registry(self):
        return read_registry(os.path.join(self.results, "registry.json"))

    def parsed(self, rows, name="test.csv"):
        """The rows as the entry point reads them back (registry-checked)."""
        write_csv(self.results, name, rows)
        with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
            return read_results(self.results, self.registry())

    def plot(self, *args):
        return run_main("--results", self.results, "--out", self.out, *args)

    def assert_png(self, name):
        path = os.path.join(self.out, name)
        self.assertTrue(os.path.isfile(path), f"{name} missing; have {pngs(self.out)}")
        with open(path, "rb") as handle:
            self.assertEqual(handle.read(8), PNG_MAGIC)


def linear_timing_rows():
    """knn and build timings of kd_tree and brute_force on two workloads, time = 5 n exactly."""
    rows = []
    for n in NS:
        for structure in ("kd_tree", "brute_force"):
            for workload in ("uniform", "clusters"):
                rows.append(row(structure=structure, workload=workload, n=n, value=5.0 * n))
                rows.append(row(structure=structure, workload=workload, n=n, operation="build",
                                params="", metric="build_time", value=5.0 * n, unit="s"))
    return rows
