"""Reading the tables and the registry (spatialplots/io.py, spatialplots/registry.py)."""

import json
import os
import subprocess
import sys

from . import support
from .support import NS, row, write_csv
from spatialplots.registry import Registry, RegistryError

REGISTRY = support.registry_dict(
    [support.suite("knn", baseline="kd_tree")],
    [support.structure("kd_tree", settings={"leaf_capacity": "16"}), support.structure("brute_force", kind="oracle")])


class TablesTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_unknown_suites_and_bad_files_are_skipped(self):
        open(os.path.join(self.results, "empty.csv"), "w").close()
        write_csv(self.results, "header_only.csv", [])
        write_csv(self.results, "no_schema.csv", [[1, 2, 3]], header=["a", "b", "c"])
        write_csv(self.results, "short_rows.csv", [["knn", "kd_tree"]])
        write_csv(self.results, "mystery.csv",
                  [row(suite="mystery", n=n, value=5.0 * n) for n in NS])
        code, _, stderr = self.plot()
        self.assertEqual(code, 0)
        self.assertIn("mystery", stderr)
        self.assertIn("empty.csv", stderr)
        self.assertFalse(os.path.isdir(self.out) and support.pngs(self.out))

    def test_unknown_suite_next_to_known_one(self):
        rows = [row(n=n, value=5.0 * n) for n in NS] + [row(suite="mystery", n=n, value=5.0 * n) for n in NS]
        write_csv(self.results, "all.csv", rows)
        code, _, stderr = self.plot()
        self.assertEqual(code, 0)
        self.assertIn("skip suite 'mystery' (4 rows) in all.csv", stderr)
        self.assertFalse([name for name in support.pngs(self.out) if name.startswith("mystery")])
        self.assert_png("knn_knn_k10_3d_double.png")

    def test_structure_missing_from_the_registry_is_skipped_with_a_note(self):
        rows = [row(n=n, value=5.0 * n) for n in NS] + [row(structure="mystery_tree", n=n, value=1.0)
                                                        for n in NS]
        write_csv(self.results, "knn.csv", rows)
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertIn("skip structure 'mystery_tree' (4 rows) in knn.csv: not in", stderr)
        self.assertIn("registry.json", stderr)
        self.assert_png("knn_knn_k10_3d_double.png")
        rows = self.parsed(rows, "knn.csv")
        self.assertEqual({r.structure for r in rows}, {"kd_tree"})

    def test_tuning_sweep_rows_stay_out_of_the_curves(self):
        rows = [row(n=n, value=5.0 * n) for n in NS] + [
            row(n=NS[-1], params="k=10;leaf_capacity=32", value=1.0),
            row(n=NS[-1], params="k=10;leaf_capacity=32", metric="best_peer_ratio", value=0.9, unit="ratio")]
        write_csv(self.results, "knn.csv", rows)
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertIn("knn.csv: 2 tuning-sweep row(s) kept out of the curves", stderr)
        self.assert_png("knn_knn_k10_3d_double.png")
        self.assertFalse([name for name in support.pngs(self.out) if "leaf_capacity" in name])

    def test_missing_results_directory(self):
        code, _, stderr = support.run_main("--results", os.path.join(self.results, "absent"),
                                           "--out", self.out)
        self.assertEqual(code, 0)
        self.assertIn("nothing to plot", stderr)

    def test_malformed_rows_are_counted(self):
        write_csv(self.results, "knn.csv", [row(n=n, value=5.0 * n) for n in NS]
                  + [row(n="many"), row(value=float("nan"))])
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertIn("skipped 2 malformed row(s)", stderr)


class RegistryFileTest(support.ResultsTestCase):
    REGISTRY = None  # each test writes its own (or none)

    def test_missing_registry_is_an_error_naming_the_file(self):
        write_csv(self.results, "knn.csv", [row(n=n, value=5.0 * n) for n in NS])
        code, stdout, stderr = self.plot()
        self.assertEqual(code, 1)
        self.assertIn(os.path.join(self.results, "registry.json"), stderr)
        self.assertIn("no such file", stderr)
        self.assertEqual(stdout, "")
        self.assertFalse(os.path.isdir(self.out))
        # The same from the command line.
        done = subprocess.run([sys.executable, support.SCRIPT, "--results", self.results,
                               "--out", self.out], capture_output=True, text=True, timeout=300)
        self.assertEqual(done.returncode, 1, done.stderr)
        self.assertIn("registry.json", done.stderr)

    def test_malformed_registry_is_an_error_naming_the_file(self):
        write_csv(self.results, "knn.csv", [row(n=n, value=5.0 * n) for n in NS])
        path = os.path.join(self.results, "registry.json")
        bad = [
            "{not json",
            json.dumps([]),
            json.dumps(dict(REGISTRY, schema_version=2)),
            json.dumps(dict(REGISTRY, suites={"knn": {}})),
            json.dumps(dict(REGISTRY, structures=[{"family": "x"}])),
            json.dumps(dict(REGISTRY, structures=[dict(support.structure("kd_tree"), kind=3)])),
            json.dumps(dict(REGISTRY, structures=[dict(support.structure("kd_tree"), complexity={"*": 1})])),
            json.dumps(dict(REGISTRY, structures=[support.structure("kd_tree")] * 2)),
            json.dumps(dict(REGISTRY, suites=[support.suite("collide", targets=[{"metric": "speedup"}])])),
        ]
        for text in bad:
            with self.subTest(text=text[:60]):
                with open(path, "w") as handle:
                    handle.write(text)
                code, _, stderr = self.plot()
                self.assertEqual(code, 1)
                self.assertIn(path, stderr)
                self.assertIn("error", stderr)

    def test_empty_results_need_no_registry(self):
        code, _, stderr = self.plot()
        self.assertEqual(code, 0)
        self.assertIn("nothing to plot", stderr)


class RegistryObjectTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_defaults_and_lookups(self):
        registry = Registry.from_dict({"schema_version": 1, "suites": [{"name": "knn"}],
                                       "structures": [{"name": "kd_tree"},
                                                      {"name": "bvh_obb", "family": "bvh",
                                                       "settings": {"bv": "obb", "leaf": 4}}]})
        self.assertEqual(registry.baseline("knn"), "")
        self.assertEqual(registry.structure("kd_tree").family, "kd_tree")
        self.assertEqual(registry.kind("kd_tree"), "library")
        self.assertEqual(registry.settings("bvh_obb"), {"bv": "obb", "leaf": "4"})
        self.assertEqual(registry.settings("absent"), {})
        self.assertIsNone(registry.theory_for("knn", "time_per_op", "kd_tree"))  # no complexity
        self.assertEqual(list(registry.families()), ["kd_tree", "bvh"])
        self.assertEqual(registry.bv("bvh_obb"), "obb")  # from settings when there is no bv field
        # Fields the plots do not use are ignored; kinds beyond library/peer/oracle accepted.
        registry = Registry.from_dict({"schema_version": 1, "suites": [], "structures": [
            {"name": "morton_array", "kind": "example", "bv": "", "suites": ["knn"], "max_n": 100000,
             "size_class": "slow"},
            {"name": "bvh", "family": "bvh", "bv": "aabb", "settings": {"builder": "sah"}}]})
        self.assertEqual(registry.kind("morton_array"), "example")
        self.assertEqual(registry.bv("bvh"), "aabb")
        with self.assertRaises(RegistryError):
            Registry.from_dict({"schema_version": 1, "suites": [], "structures": [{"name": ""}]})
