"""The complexity-curves family (spatialplots/families/complexity.py) and the fit behind it."""

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from . import support  # noqa: E402
from .support import NS, row, write_csv  # noqa: E402
from spatialplots.core import COMPLEXITY_FUNCTIONS, fit_exponent  # noqa: E402
from spatialplots.figures import draw_complexity_panel  # noqa: E402
from spatialplots.registry import Registry  # noqa: E402
from spatialplots.style import StyleBook  # noqa: E402

REGISTRY = support.registry_dict(
    [support.suite("knn", baseline="kd_tree"),
     support.suite("bv", series_params=["method"])],
    [support.structure("kd_tree"), support.structure("octree"),
     support.structure("brute_force", kind="oracle"),
     support.structure("spatialbench"), support.structure("cgal", kind="peer")])


class FitExponentTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_exact_power_laws(self):
        self.assertAlmostEqual(fit_exponent(NS, [5.0 * n for n in NS]), 1.0, delta=1e-9)
        self.assertAlmostEqual(fit_exponent(NS, [3.0 * n ** 0.5 for n in NS]), 0.5, delta=1e-9)
        self.assertAlmostEqual(fit_exponent(NS, [7.0] * 4), 0.0, delta=1e-9)

    def test_needs_two_distinct_n(self):
        self.assertTrue(math.isnan(fit_exponent([1000, 1000], [1.0, 2.0])))
        self.assertTrue(math.isnan(fit_exponent([], [])))

    def test_theory_mapping(self):
        registry = Registry.from_dict(REGISTRY)
        theory = registry.theory_for
        self.assertEqual(theory("build", "build_time", "kd_tree"), "n log n")
        self.assertEqual(theory("knn", "time_per_op", "kd_tree"), "log n")
        self.assertEqual(theory("knn", "time_per_op", "brute_force"), "n")
        self.assertEqual(theory("some_new_query", "time_per_op", "octree"), "log n")
        self.assertEqual(theory("some_new_build", "build_time", "octree"), "n log n")
        for entry in registry.structures.values():
            for complexity in entry.complexity.values():
                self.assertIn(complexity, COMPLEXITY_FUNCTIONS)
        # The grey line follows the suite baseline's theory, not the linear scan's.
        self.assertEqual(registry.reference_theory("knn", "build", "build_time",
                                                   ["brute_force", "kd_tree"]), "n log n")
        # Without a baseline: the most common theory among the non-oracle structures.
        self.assertEqual(registry.reference_theory("bv", "build", "build_time",
                                                   ["brute_force", "octree"]), "n log n")

    def test_legend_shows_exponent_and_theory(self):
        registry = Registry.from_dict(REGISTRY)
        figure, axis = plt.subplots()
        series = {("kd_tree", True): {n: [5.0 * n] for n in NS}}
        draw_complexity_panel(axis, series, "knn", "time_per_op", "ns", "uniform",
                              StyleBook(registry, ["kd_tree"]), registry, "knn")
        labels = [text.get_text() for text in axis.get_legend().get_texts()]
        plt.close(figure)
        self.assertIn("kd_tree (n^1.00)", labels)
        self.assertIn("theory O(log n)", labels)

    def test_theory_line_is_not_anchored_at_the_oracle(self):
        # brute force builds trivially fast (time = n), kd_tree in 10 n log n: the line is
        # still the tree's n log n.
        registry = Registry.from_dict(REGISTRY)
        figure, axis = plt.subplots()
        series = {("kd_tree", True): {n: [10.0 * n * math.log(n)] for n in NS},
                  ("brute_force", True): {n: [1.0 * n] for n in NS}}
        draw_complexity_panel(axis, series, "build", "build_time", "s", "uniform",
                              StyleBook(registry, []), registry, "knn")
        labels = [text.get_text() for text in axis.get_legend().get_texts()]
        plt.close(figure)
        self.assertIn("theory O(n log n)", labels)


class ComplexityFiguresTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_one_figure_per_operation_and_metric(self):
        rows = support.linear_timing_rows()
        # One n only: no curve, and a note.
        rows.append(row(structure="kd_tree", operation="radius", params="r=1", n=1000))
        write_csv(self.results, "knn.csv", rows)
        code, stdout, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertEqual(support.pngs(self.out), ["knn_build_3d_double.png", "knn_knn_k10_3d_double.png",
                                                 "knn_summary.png"])
        self.assertIn("only one n", stderr)
        self.assertIn("knn_knn_k10_3d_double.png", stdout)

    def test_series_params_split_by_bv(self):
        rows = []
        for n in (1000, 100000):
            for structure, bv, method in (("spatialbench", "obb", "dito"), ("spatialbench", "obb", "pca"),
                                          ("cgal", "obb", "oriented_bounding_box"),
                                          ("spatialbench", "aabb", "minmax")):
                rows.append(row(suite="bv", structure=structure, bv=bv, workload="sphere", n=n,
                                operation="fit", params=f"method={method}", metric="fit_time",
                                value=1e-8 * n, unit="s"))
        write_csv(self.results, "bv.csv", rows)
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertEqual(support.pngs(self.out), ["bv_aabb_fit_3d_double.png", "bv_obb_fit_3d_double.png"])
