"""Tests for plots/plot_results.py.

Run from the repository root with Debian's interpreter:
    /usr/bin/python3 -m unittest plots/test_plot_results.py
Everything is written to temporary directories; results/ and plots/ are not touched.
"""

import contextlib
import csv
import importlib.util
import io
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "plot_results.py")

_spec = importlib.util.spec_from_file_location("plot_results", SCRIPT)
plot_results = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(plot_results)

HEADER = ["suite", "structure", "bv", "workload", "n", "dim", "scalar", "operation", "params",
          "metric", "value", "unit", "validated", "run_id"]
NS = [1000, 10000, 100000, 1000000]


def row(suite="knn", structure="kd_tree", workload="uniform", n=1000, operation="knn",
        params="k=10", metric="time_per_op", value=1.0, unit="ns", validated="true"):
    return [suite, structure, "", workload, n, 3, "double", operation, params, metric,
            repr(value), unit, validated, "test-run"]


def write_csv(directory, name, rows, header=HEADER):
    with open(os.path.join(directory, name), "w", newline="") as handle:
        writer = csv.writer(handle)
        if header is not None:
            writer.writerow(header)
        writer.writerows(rows)


def known_exponent_rows():
    """time = 5 n exactly for every timing; recall and ratio rows for the other two plots."""
    rows = []
    for n in NS:
        for structure in ("kd_tree", "brute_force"):
            for workload in ("uniform", "clusters"):
                rows.append(row(structure=structure, workload=workload, n=n, value=5.0 * n))
                rows.append(row(structure=structure, workload=workload, n=n, operation="build",
                                params="", metric="build_time", value=5.0 * n, unit="s"))
        for eps in (0, 0.5, 1, 2):
            params = f"k=10;eps={eps}"
            rows.append(row(n=n, operation="approx_knn", params=params,
                            value=5.0 * n / (1 + eps)))
            rows.append(row(n=n, operation="approx_knn", params=params, metric="recall",
                            value=1.0 - 0.1 * eps, unit="ratio"))
        rows.append(row(structure="nanoflann", n=n, metric="time_ratio", value=1.2, unit="ratio"))
    return rows


def run_main(*args):
    """main(args) with stdout and stderr captured; returns (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = plot_results.main(list(args))
    return code, out.getvalue(), err.getvalue()


def pngs(directory):
    return sorted(name for name in os.listdir(directory) if name.endswith(".png"))


class FitExponentTest(unittest.TestCase):
    def test_exact_power_laws(self):
        self.assertAlmostEqual(plot_results.fit_exponent(NS, [5.0 * n for n in NS]), 1.0,
                               delta=1e-9)
        self.assertAlmostEqual(plot_results.fit_exponent(NS, [3.0 * n ** 0.5 for n in NS]), 0.5,
                               delta=1e-9)
        self.assertAlmostEqual(plot_results.fit_exponent(NS, [7.0] * 4), 0.0, delta=1e-9)

    def test_needs_two_distinct_n(self):
        self.assertTrue(math.isnan(plot_results.fit_exponent([1000, 1000], [1.0, 2.0])))
        self.assertTrue(math.isnan(plot_results.fit_exponent([], [])))

    def test_theory_mapping(self):
        theory = plot_results.theory_for
        self.assertEqual(theory("build", "build_time", "kd_tree"), "n log n")
        self.assertEqual(theory("knn", "time_per_op", "kd_tree"), "log n")
        self.assertEqual(theory("knn", "time_per_op", "brute_force"), "n")
        self.assertEqual(theory("some_new_query", "time_per_op", "octree"), "log n")
        self.assertEqual(theory("some_new_build", "build_time", "octree"), "n log n")
        for entry in plot_results.THEORY.values():
            for complexity in entry.values():
                self.assertIn(complexity, plot_results.COMPLEXITY_FUNCTIONS)

    def test_legend_shows_exponent_and_theory(self):
        import matplotlib.pyplot as plt
        figure, axis = plt.subplots()
        series = {("kd_tree", True): {n: [5.0 * n] for n in NS}}
        plot_results.draw_complexity_panel(axis, series, "knn", "time_per_op", "ns", "uniform",
                                           plot_results.StyleBook(["kd_tree"]))
        labels = [text.get_text() for text in axis.get_legend().get_texts()]
        plt.close(figure)
        self.assertIn("kd_tree (n^1.00)", labels)
        self.assertIn("theory O(log n)", labels)


class PlotFilesTest(unittest.TestCase):
    def setUp(self):
        self._temp = tempfile.TemporaryDirectory()
        self.results = os.path.join(self._temp.name, "results")
        self.out = os.path.join(self._temp.name, "out")
        os.makedirs(self.results)

    def tearDown(self):
        self._temp.cleanup()

    def assert_png(self, name):
        path = os.path.join(self.out, name)
        self.assertTrue(os.path.isfile(path), f"{name} missing; have {pngs(self.out)}")
        with open(path, "rb") as handle:
            self.assertEqual(handle.read(8), b"\x89PNG\r\n\x1a\n")

    def test_pngs_are_created(self):
        write_csv(self.results, "knn.csv", known_exponent_rows())
        code, stdout, _ = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0)
        for name in ("knn_knn_k10_3d_double.png", "knn_build_3d_double.png",
                     "knn_recall_vs_time_uniform_3d_double.png", "knn_ratios.png"):
            self.assert_png(name)
        # Atomic writes leave no temporary files behind.
        self.assertEqual([name for name in os.listdir(self.out) if not name.endswith(".png")], [])
        self.assertIn("knn_knn_k10_3d_double.png", stdout)

    def test_unknown_suites_and_bad_files_are_skipped(self):
        open(os.path.join(self.results, "empty.csv"), "w").close()
        write_csv(self.results, "header_only.csv", [])
        write_csv(self.results, "no_schema.csv", [[1, 2, 3]], header=["a", "b", "c"])
        write_csv(self.results, "short_rows.csv", [["knn", "kd_tree"]])
        write_csv(self.results, "mystery.csv",
                  [row(suite="mystery", n=n, value=5.0 * n) for n in NS])
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0)
        self.assertIn("mystery", stderr)
        self.assertIn("empty.csv", stderr)
        self.assertFalse(os.path.isdir(self.out) and pngs(self.out))

    def test_unknown_suite_next_to_known_one(self):
        rows = known_exponent_rows() + [row(suite="mystery", n=n, value=5.0 * n) for n in NS]
        write_csv(self.results, "all.csv", rows)
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0)
        self.assertIn("skip suite 'mystery'", stderr)
        self.assertFalse([name for name in pngs(self.out) if name.startswith("mystery")])
        self.assert_png("knn_knn_k10_3d_double.png")

    def test_missing_results_directory(self):
        code, _, stderr = run_main("--results", os.path.join(self.results, "absent"),
                                   "--out", self.out)
        self.assertEqual(code, 0)
        self.assertIn("nothing to plot", stderr)

    def test_unvalidated_timings_are_skipped_unless_asked(self):
        write_csv(self.results, "knn.csv",
                  [row(n=n, value=5.0 * n, validated="false") for n in NS])
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0)
        self.assertIn("unvalidated", stderr)
        self.assertEqual(pngs(self.out), [])
        code, _, _ = run_main("--results", self.results, "--out", self.out,
                              "--include-unvalidated")
        self.assertEqual(code, 0)
        self.assert_png("knn_knn_k10_3d_double.png")

    def test_command_line(self):
        write_csv(self.results, "knn.csv", known_exponent_rows())
        done = subprocess.run([sys.executable, SCRIPT, "--results", self.results,
                               "--out", self.out], capture_output=True, text=True, timeout=300)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assert_png("knn_build_3d_double.png")


def bv_row(structure, bv, method, workload, n, operation, metric, value, unit, test=None):
    params = f"method={method}" + (f";test={test}" if test else "")
    return ["bv", structure, bv, workload, n, 3, "double", operation, params, metric,
            repr(value), unit, "true", "test-run"]


class BvTradeoffTest(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory()
        self.results = os.path.join(self._tmp.name, "results")
        self.out = os.path.join(self._tmp.name, "plots")
        os.makedirs(self.results)

    def tearDown(self):
        self._tmp.cleanup()

    def test_pareto_front(self):
        points = [(1, 5), (2, 3), (3, 4), (4, 1), (0.5, 9), (4, 2)]
        # (3, 4) is dominated by (2, 3); (4, 2) by (4, 1).
        self.assertEqual(plot_results.pareto_front(points), [4, 0, 1, 3])

    def test_points_are_geometric_means_over_shapes_at_the_reference_n(self):
        rows = []
        for workload, scale in (("sphere", 1.0), ("elongated", 4.0)):
            for n in (1000, 100000, 1000000):
                rows.append(plot_results.Row("bv", "spatialbench", "aabb", workload, n, 3, "double",
                                             "fit", "method=minmax", "fit_time", scale * n,
                                             "s", True, "r"))
                rows.append(plot_results.Row("bv", "spatialbench", "aabb", workload, n, 3, "double",
                                             "fit", "method=minmax", "tightness", scale, "ratio",
                                             True, "r"))
        points = plot_results.bv_points(rows, "fit", "fit_time", "tightness",
                                        lambda ns: 100000 if 100000 in ns else max(ns))
        self.assertEqual(len(points), 1)
        label, x, y = points[0]
        self.assertEqual(label, "aabb minmax")
        self.assertAlmostEqual(x, 2.0 * 100000)  # sqrt(1 * 4) * 1e5
        self.assertAlmostEqual(y, 2.0)

    def test_bv_plots_are_written(self):
        rows = []
        for workload in ("sphere", "elongated"):
            for n in (1000, 100000):
                for bv, method, t, tight in (("aabb", "minmax", 1e-4, 3.0), ("sphere", "ritter", 2e-4, 4.0),
                                             ("obb", "dito", 1e-3, 1.5)):
                    rows.append(bv_row("spatialbench", bv, method, workload, n, "fit", "fit_time",
                                       t * n / 1000, "s"))
                    rows.append(bv_row("spatialbench", bv, method, workload, n, "fit", "tightness", tight,
                                       "ratio"))
            for bv, method, t, fp in (("aabb", "minmax", 3.0, 0.2), ("sphere", "ritter", 2.0, 0.4),
                                      ("obb", "dito", 20.0, 0.05)):
                rows.append(bv_row("spatialbench", bv, method, workload, 200, "overlap", "time_per_op",
                                   t, "ns", test="t"))
                rows.append(bv_row("spatialbench", bv, method, workload, 200, "overlap",
                                   "false_positive_rate_shapes", fp, "ratio", test="t"))
        write_csv(self.results, "bv.csv", rows)
        code, _, _ = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0)
        names = pngs(self.out)
        self.assertIn("bv_tradeoff.png", names)
        # Fit-time curves are split by volume type, one curve per method.
        self.assertIn("bv_obb_fit_3d_double.png", names)


class RaycastPlotTest(unittest.TestCase):
    def setUp(self):
        self._temp = tempfile.TemporaryDirectory()
        self.results = os.path.join(self._temp.name, "results")
        self.out = os.path.join(self._temp.name, "out")
        os.makedirs(self.results)

    def tearDown(self):
        self._temp.cleanup()

    @staticmethod
    def rows():
        rows = []
        for params in ("rays=incoherent", "rays=coherent;camera=128x128"):
            for workload in ("sphere", "soup"):
                for n in NS:
                    rows.append(row(suite="raycast", structure="embree", workload=workload, n=n,
                                    operation="ray", params=params, value=100.0 * math.log(n)))
                    rows.append(row(suite="raycast", structure="cgal_aabb_tree", workload=workload,
                                    n=n, operation="ray", params=params, value=0.5 * n))
                    # Two runs of one point: the median is drawn.
                    rows.append(row(suite="raycast", structure="cgal_aabb_tree", workload=workload,
                                    n=n, operation="ray", params=params, value=1.5 * n))
                # A structure whose timings were never validated must not be drawn.
                rows.append(row(suite="raycast", structure="broken", workload=workload, n=1000,
                                operation="ray", params=params, value=1.0, validated="false"))
            rows.append(row(suite="raycast", structure="embree", workload="real:bunny.obj", n=69666,
                            operation="ray", params=params, value=0.3, unit="us"))
        rows.append(row(suite="raycast", structure="embree", workload="sphere", n=1000,
                        operation="build", params="", metric="build_time", value=0.01, unit="s"))
        return rows

    def test_series_follow_the_validation_rule_and_take_medians(self):
        write_csv(self.results, "raycast.csv", self.rows())
        with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
            parsed = plot_results.read_results(self.results)
            series, unit = plot_results.raycast_series(parsed)
        self.assertEqual(unit, "s")  # ns and us rows mixed: drawn in seconds
        self.assertEqual(sorted(series), ["rays=coherent;camera=128x128", "rays=incoherent"])
        keys = series["rays=incoherent"]
        self.assertNotIn(("broken", "sphere", False), keys)
        self.assertAlmostEqual(keys[("cgal_aabb_tree", "soup", True)][10000], 1e-9 * 10000)
        self.assertAlmostEqual(keys[("embree", "real:bunny.obj", True)][69666], 0.3e-6)
        # Exponents: linear for cgal here, flat-ish (log n) for embree.
        cgal = keys[("cgal_aabb_tree", "sphere", True)]
        self.assertAlmostEqual(plot_results.fit_exponent(sorted(cgal), [cgal[n] for n in sorted(cgal)]),
                               1.0, delta=1e-9)

    def test_raycast_figure_is_written(self):
        write_csv(self.results, "raycast.csv", self.rows())
        code, stdout, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0, stderr)
        names = pngs(self.out)
        self.assertIn(plot_results.RAYCAST_FILE, names)
        self.assertIn("raycast_ray_raysincoherent_3d_double.png", names)  # the generic curves too
        self.assertIn("unvalidated", stderr)
        with open(os.path.join(self.out, plot_results.RAYCAST_FILE), "rb") as handle:
            self.assertEqual(handle.read(8), b"\x89PNG\r\n\x1a\n")

    def test_bvh_tradeoff_points_take_the_largest_n_and_the_validation_rule(self):
        def bvh_row(structure, bv, n, operation, params, metric, value, unit, validated="true"):
            r = row(suite="raycast", structure=structure, workload="sphere", n=n, operation=operation,
                    params=params, metric=metric, value=value, unit=unit, validated=validated)
            r[2] = bv
            return r
        rows = []
        for n in (1000, 100000):
            for structure, bv, ratio in (("bvh", "aabb", 1.0), ("bvh_obb", "obb", 0.6),
                                         ("bvh_median", "aabb", 1.0)):
                rows.append(bvh_row(structure, bv, n, "build", "", "node_area_ratio", ratio, "ratio"))
                rows.append(bvh_row(structure, bv, n, "build", "", "build_time", 1e-6 * n, "s"))
                rows.append(bvh_row(structure, bv, n, "ray", "rays=incoherent", "time_per_op",
                                    2.0 if structure == "bvh_obb" else 1.0, "us"))
                rows.append(bvh_row(structure, bv, n, "ray", "rays=coherent;camera=8x8", "time_per_op",
                                    50.0, "ns"))
        # An unvalidated timing drops that point (not the others).
        rows.append(bvh_row("bvh_sphere", "sphere", 100000, "build", "", "node_area_ratio", 1.3, "ratio"))
        rows.append(bvh_row("bvh_sphere", "sphere", 100000, "build", "", "build_time", 0.2, "s", "false"))
        rows.append(bvh_row("bvh_sphere", "sphere", 100000, "ray", "rays=incoherent", "time_per_op", 3.0,
                            "us"))
        write_csv(self.results, "raycast.csv", rows)
        with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
            parsed = plot_results.read_results(self.results)
        data = plot_results.bvh_tradeoff_points(parsed, include_unvalidated=False)
        self.assertEqual(list(data), ["sphere"])
        entry = data["sphere"]
        self.assertEqual(entry["n"], 100000)
        def rounded(items):
            return sorted(tuple(round(v, 9) if isinstance(v, float) else v for v in item) for item in items)
        self.assertEqual(rounded(entry["points"]), [("aabb", 1.0, 0.1, 1000.0), ("obb", 0.6, 0.1, 2000.0)])
        self.assertEqual(rounded(entry["builders"]),
                         [("SAH", 1000, 0.001, 1000.0), ("SAH", 100000, 0.1, 1000.0),
                          ("median", 1000, 0.001, 1000.0), ("median", 100000, 0.1, 1000.0)])
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0, stderr)
        self.assertIn(plot_results.BVH_TRADEOFF_FILE, pngs(self.out))


def collide_row(structure, workload, n, operation, metric, value, unit="s", params="overlaps_per_box=2",
                bv="-", validated="true", suite="collide"):
    return [suite, structure, bv, workload, n, 3, "double", operation, params, metric, repr(value), unit,
            validated, "test-run"]


COLLIDE_NS = (1000, 10000)
MOVING = "overlaps_per_box=2;steps=3;speed=side/4"


def collide_boxes_rows():
    """build_and_self_pairs times: cgal 10 us per box, collision_grid exactly 5x faster, bvh 2x."""
    rows = []
    for n in COLLIDE_NS:
        for structure, bv, factor in (("cgal_box_intersection", "-", 1.0), ("collision_grid", "-", 5.0),
                                      ("bvh", "aabb", 2.0)):
            rows.append(collide_row(structure, "boxes", n, "build_and_self_pairs", "time", 1e-5 * n / factor,
                                    bv=bv))
            rows.append(collide_row(structure, "boxes", n, "build", "time", 0.5e-5 * n / factor, bv=bv))
            rows.append(collide_row(structure, "boxes", n, "build", "memory", 64.0 * n, unit="bytes", bv=bv))
            rows.append(collide_row(structure, "boxes", n, "self_pairs", "pairs", 1.0 * n, unit="count", bv=bv))
    return rows


def collide_moving_rows():
    rows = []
    for n in COLLIDE_NS:
        for structure in ("collision_grid", "fcl_dynamic_aabb_tree", "bvh_refit", "bvh_rebuild"):
            bv = "aabb" if structure.startswith("bvh") else "-"
            rows.append(collide_row(structure, "moving_boxes", n, "build", "time", 1e-6 * n, params=MOVING,
                                    bv=bv))
            rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs", "time", 1e-7 * n,
                                    params=MOVING, bv=bv))
            rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs", "steps_per_second",
                                    1e7 / n, unit="1/s", params=MOVING, bv=bv))
            rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs",
                                    "pairs_changed_per_step", 0.1 * n, unit="count", params=MOVING, bv=bv))
            if structure.startswith("bvh"):
                for step in (1, 2, 3):
                    grows = structure == "bvh_refit"
                    rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs", "quality",
                                            40.0 + (5.0 * step if grows else 0.0), unit="ratio",
                                            params=f"{MOVING};step={step}", bv=bv))
                    rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs", "time",
                                            1e-7 * n * (1 + 0.1 * step if grows else 1.0),
                                            params=f"{MOVING};step={step}", bv=bv))
    return rows


def collide_triangle_rows():
    rows = []
    for bv, candidates, fp, exact, build in (("aabb", 3000, 0.9, 1e-3, 1e-3), ("obb", 1500, 0.8, 2e-3, 4e-3),
                                             ("sphere", 2800, 0.88, 0.9e-3, 2e-3)):
        structure = f"bvh_{bv}"
        rows.append(collide_row(structure, "triangles", 2000, "build", "time", build, params="soup", bv=bv))
        rows.append(collide_row(structure, "triangles", 2000, "candidate_pairs", "time", exact / 2,
                                params="soup", bv=bv))
        rows.append(collide_row(structure, "triangles", 2000, "exact_pairs", "time", exact, params="soup", bv=bv))
        rows.append(collide_row(structure, "triangles", 2000, "candidate_pairs", "pairs", candidates,
                                unit="count", params="soup", bv=bv))
        rows.append(collide_row(structure, "triangles", 2000, "exact_pairs", "pairs", 300, unit="count",
                                params="soup", bv=bv))
        rows.append(collide_row(structure, "triangles", 2000, "candidate_pairs", "false_positive_ratio", fp,
                                unit="ratio", params="soup", bv=bv))
    return rows


def scenes_rows():
    rows = []
    params = "steps=100;strategy=automatic;filter=exact"
    for scene, stages in (("boxes_100k", ("motion", "update", "collide_broad_phase", "collide_narrow_phase")),
                          ("queries", ("motion", "churn", "update", "raycast", "nearest", "range"))):
        for structure, bv in (("collision_grid", "-"), ("bvh", "aabb")):
            rows.append(collide_row(structure, scene, 100000, "build", "time", 0.05, params=params, bv=bv,
                                    suite="scenes"))
            for i, stage in enumerate(stages):
                rows.append(collide_row(structure, scene, 100000, stage, "time", 0.001 * (i + 1), params=params,
                                        bv=bv, suite="scenes"))
            total = 0.001 * sum(range(1, len(stages) + 1)) + 0.002
            rows.append(collide_row(structure, scene, 100000, "step", "time", total, params=params, bv=bv,
                                    suite="scenes"))
            rows.append(collide_row(structure, scene, 100000, "step", "steps_per_second", 1.0 / total,
                                    unit="1/s", params=params, bv=bv, suite="scenes"))
            rows.append(collide_row(structure, scene, 100000, "step", "pairs", 1000, unit="count",
                                    params=params, bv=bv, suite="scenes"))
    return rows


COLLIDE_FILES = ("collide_boxes.png", "collide_moving.png", "collide_refit_decay.png",
                 "collide_bv_tradeoff.png")


class CollidePlotTest(unittest.TestCase):
    def setUp(self):
        self._temp = tempfile.TemporaryDirectory()
        self.results = os.path.join(self._temp.name, "results")
        self.out = os.path.join(self._temp.name, "out")
        os.makedirs(self.results)

    def tearDown(self):
        self._temp.cleanup()

    def parsed(self, rows, name="collide.csv"):
        write_csv(self.results, name, rows)
        with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
            return plot_results.read_results(self.results)

    def test_suites_are_known_and_dash_means_no_bv(self):
        self.assertIn("collide", plot_results.SUITES)
        self.assertIn("scenes", plot_results.SUITES)  # the runner's suite name
        self.assertNotIn("scene", plot_results.SUITES)
        parsed = self.parsed(collide_boxes_rows())
        grid = [r for r in parsed if r.structure == "collision_grid"]
        self.assertTrue(grid)
        self.assertEqual({r.bv for r in grid}, {""})
        self.assertEqual(plot_results.label_of(grid[0]), "collision_grid")

    def test_speedup_is_baseline_time_over_time(self):
        series = {("cgal_box_intersection", True): {1000: 10.0, 10000: 100.0},
                  ("collision_grid", True): {1000: 2.0, 10000: 20.0},
                  ("bvh<aabb>", True): {1000: 4.0, 100000: 1.0},  # 1e5: no cgal time, no ratio
                  ("fcl_sap", False): {10000: 400.0}}
        ratios = plot_results.speedups(series)
        self.assertEqual(ratios, {("collision_grid", True): {1000: 5.0, 10000: 5.0},
                                  ("bvh<aabb>", True): {1000: 2.5},
                                  ("fcl_sap", False): {10000: 0.25}})
        self.assertEqual(plot_results.speedups({("bvh", True): {1000: 1.0}}), {})

    def test_speedup_from_csv_takes_medians(self):
        rows = collide_boxes_rows()
        # Two more runs of cgal at 1e3: the median (the original) is kept.
        rows.append(collide_row("cgal_box_intersection", "boxes", 1000, "build_and_self_pairs", "time", 1.0))
        rows.append(collide_row("cgal_box_intersection", "boxes", 1000, "build_and_self_pairs", "time", 1e-9))
        # An unvalidated, absurdly fast grid timing is not drawn.
        rows.append(collide_row("collision_grid", "boxes", 1000, "build_and_self_pairs", "time", 1e-12,
                                validated="false"))
        parsed = self.parsed(rows)
        with contextlib.redirect_stderr(io.StringIO()):
            data = plot_results.collide_boxes_series(parsed, include_unvalidated=False)
        self.assertEqual(list(data), [("overlaps_per_box=2", 3, "double")])
        ratios = plot_results.speedups(plot_results.median_points(data[("overlaps_per_box=2", 3, "double")]))
        self.assertEqual(sorted(ratios), [("bvh<aabb>", True), ("collision_grid", True)])
        for n in COLLIDE_NS:
            self.assertAlmostEqual(ratios[("collision_grid", True)][n], 5.0, delta=1e-9)
            self.assertAlmostEqual(ratios[("bvh<aabb>", True)][n], 2.0, delta=1e-9)

    def test_refit_decay_and_moving_series(self):
        parsed = self.parsed(collide_moving_rows())
        decay = plot_results.refit_decay_series(parsed, include_unvalidated=False)
        self.assertEqual(sorted(decay), [(n, MOVING) for n in COLLIDE_NS])
        quality = decay[(1000, MOVING)]["quality"]
        self.assertEqual(quality[("bvh_refit<aabb>", True)], {1: 45.0, 2: 50.0, 3: 55.0})
        self.assertEqual(quality[("bvh_rebuild<aabb>", True)], {1: 40.0, 2: 40.0, 3: 40.0})
        self.assertAlmostEqual(decay[(1000, MOVING)]["time"][("bvh_rebuild<aabb>", True)][2], 0.1)  # ms
        groups, bars, changed = plot_results.collide_moving_bars(parsed, include_unvalidated=False)
        self.assertEqual(groups, [(n, MOVING) for n in COLLIDE_NS])
        self.assertAlmostEqual(bars[("collision_grid", True)][(10000, MOVING)], 1000.0)
        self.assertAlmostEqual(changed[(10000, MOVING)], 1000.0)

    def test_all_figures_are_written(self):
        write_csv(self.results, "collide.csv",
                  collide_boxes_rows() + collide_moving_rows() + collide_triangle_rows())
        write_csv(self.results, "scenes.csv", scenes_rows())
        code, stdout, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0, stderr)
        # Only the dedicated figures: no generic complexity curves of these suites.
        self.assertEqual(pngs(self.out), sorted(COLLIDE_FILES + ("scenes.png",)))
        for name in pngs(self.out):
            with open(os.path.join(self.out, name), "rb") as handle:
                self.assertEqual(handle.read(8), b"\x89PNG\r\n\x1a\n")
            self.assertIn(name, stdout)
        self.assertNotIn("skip collide", stderr)

    def test_missing_workloads_are_skipped_with_a_note(self):
        write_csv(self.results, "collide.csv", collide_boxes_rows())
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0, stderr)
        self.assertEqual(pngs(self.out), ["collide_boxes.png"])
        for name in COLLIDE_FILES[1:]:
            self.assertIn(f"skip {name}", stderr)

    def test_only_moving_boxes_and_no_baseline(self):
        rows = collide_moving_rows() + [r for r in collide_boxes_rows() if r[1] != "cgal_box_intersection"]
        write_csv(self.results, "collide.csv", rows)
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0, stderr)
        self.assertEqual(pngs(self.out), ["collide_boxes.png", "collide_moving.png",
                                          "collide_refit_decay.png"])
        self.assertIn("no speed-up panel", stderr)
        self.assertIn("skip collide_bv_tradeoff.png", stderr)

    def test_unvalidated_moving_rows_are_skipped_unless_asked(self):
        rows = [r[:12] + ["false"] + r[13:] for r in collide_moving_rows()]
        write_csv(self.results, "collide.csv", rows)
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0, stderr)
        self.assertIn("unvalidated", stderr)
        self.assertIn("skip collide_moving.png", stderr)
        # Tree quality is not a timing: the decay figure still shows it.
        self.assertEqual(pngs(self.out), ["collide_refit_decay.png"])
        code, _, stderr = run_main("--results", self.results, "--out", self.out, "--include-unvalidated")
        self.assertEqual(code, 0, stderr)
        self.assertIn("collide_moving.png", pngs(self.out))

    def test_bv_points(self):
        parsed = self.parsed(collide_triangle_rows())
        points = plot_results.collide_bv_points(parsed, include_unvalidated=False)
        self.assertEqual(list(points), [("soup", 2000)])
        by_label = {p[0]: p[1:] for p in points[("soup", 2000)]}
        self.assertEqual(sorted(by_label), ["aabb", "obb", "sphere"])
        self.assertEqual(by_label["obb"], (1500.0, 0.8, 2e-3, 4e-3))

    def test_scene_stage_times(self):
        parsed = self.parsed(scenes_rows(), name="scenes.csv")
        times, rates = plot_results.scene_stage_times(parsed, include_unvalidated=False)
        self.assertEqual(sorted(times), [("boxes_100k", 100000), ("queries", 100000)])
        params = "steps=100;strategy=automatic;filter=exact"
        grid = times[("queries", 100000)][("collision_grid", params, True)]
        self.assertNotIn("build", grid)  # once per scene, not a stage
        self.assertAlmostEqual(grid["churn"], 2.0)  # ms
        self.assertAlmostEqual(grid["step"], 23.0)
        self.assertAlmostEqual(rates[("queries", 100000)][("collision_grid", params, True)], 1000.0 / 23.0)
        code, _, stderr = run_main("--results", self.results, "--out", self.out)
        self.assertEqual(code, 0, stderr)
        self.assertEqual(pngs(self.out), ["scenes.png"])


if __name__ == "__main__":
    unittest.main()
