"""The recall-vs-time family (spatialplots/families/recall.py)."""

from . import support
from .support import NS, row, write_csv
from spatialplots.families import recall

REGISTRY = support.registry_dict(
    [support.suite("knn", baseline="kd_tree")],
    [support.structure("kd_tree"), support.structure("nanoflann", kind="peer")])


def approx_rows(validated="true"):
    rows = []
    for n in NS:
        for structure, scale in (("kd_tree", 1.0), ("nanoflann", 2.0)):
            for eps in (0, 0.5, 1, 2):
                params = f"k=10;eps={eps}"
                rows.append(row(structure=structure, n=n, operation="approx_knn", params=params,
                                value=scale * 5.0 * n / (1 + eps), validated=validated))
                rows.append(row(structure=structure, n=n, operation="approx_knn", params=params,
                                metric="recall", value=1.0 - 0.1 * eps, unit="ratio",
                                validated=validated))
    return rows


class RecallTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_points_pair_time_and_recall_at_the_largest_n(self):
        figures, units = recall.recall_figures(self.parsed(approx_rows()), include_unvalidated=False)
        key = ("knn", "uniform", 3, "double")
        self.assertEqual(list(figures), [key])
        self.assertEqual(units[key], {"ns"})
        self.assertEqual(max(figures[key]), NS[-1])
        points = {(label, eps): r for label, _, _, eps, _, r in figures[key][NS[-1]]}
        self.assertEqual(len(points), 8)
        self.assertAlmostEqual(points[("nanoflann", "2")], 0.8)

    def test_figure_is_written(self):
        write_csv(self.results, "knn.csv", approx_rows())
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assert_png("knn_recall_vs_time_uniform_3d_double.png")

    def test_unvalidated_times_are_skipped_unless_asked(self):
        write_csv(self.results, "knn.csv", approx_rows(validated="false"))
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertIn("skip recall-vs-time plots", stderr)
        self.assertEqual(support.pngs(self.out), [])
        code, _, stderr = self.plot("--include-unvalidated")
        self.assertEqual(code, 0, stderr)
        self.assert_png("knn_recall_vs_time_uniform_3d_double.png")
