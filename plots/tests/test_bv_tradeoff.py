"""The bounding-volume trade-off family (spatialplots/families/bv_tradeoff.py)."""

from . import support
from .support import write_csv
from spatialplots.core import pareto_front
from spatialplots.families import bv_tradeoff
from spatialplots.io import Row

# The bv suite: `method` names a curve (series_params); cgal is a peer, so "[cgal]" in labels.
REGISTRY = support.registry_dict(
    [support.suite("bv", series_params=["method"])],
    [support.structure("spatialbench"), support.structure("cgal", kind="peer")])


def bv_row(structure, bv, method, workload, n, operation, metric, value, unit, test=None):
    params = f"method={method}" + (f";test={test}" if test else "")
    return ["bv", structure, bv, workload, n, 3, "double", operation, params, metric,
            repr(value), unit, "true", "test-run"]


class BvTradeoffTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_pareto_front(self):
        points = [(1, 5), (2, 3), (3, 4), (4, 1), (0.5, 9), (4, 2)]
        # (3, 4) is dominated by (2, 3); (4, 2) by (4, 1).
        self.assertEqual(pareto_front(points), [4, 0, 1, 3])

    @staticmethod
    def fit_rows(structure):
        rows = []
        for workload, scale in (("sphere", 1.0), ("elongated", 4.0)):
            for n in (1000, 100000, 1000000):
                rows.append(Row("bv", structure, "aabb", workload, n, 3, "double", "fit",
                                "method=minmax", "fit_time", scale * n, "s", True, "r"))
                rows.append(Row("bv", structure, "aabb", workload, n, 3, "double", "fit",
                                "method=minmax", "tightness", scale, "ratio", True, "r"))
        return rows

    def points(self, rows):
        return bv_tradeoff.bv_points(rows, self.registry(), "fit", "fit_time", "tightness",
                                     lambda ns: 100000 if 100000 in ns else max(ns))

    def test_points_are_geometric_means_over_shapes_at_the_reference_n(self):
        points = self.points(self.fit_rows("spatialbench"))
        self.assertEqual(len(points), 1)
        label, x, y = points[0]
        self.assertEqual(label, "aabb minmax")
        self.assertAlmostEqual(x, 2.0 * 100000)  # sqrt(1 * 4) * 1e5
        self.assertAlmostEqual(y, 2.0)

    def test_a_peer_is_named_in_the_label(self):
        points = self.points(self.fit_rows("spatialbench") + self.fit_rows("cgal"))
        self.assertEqual([label for label, _, _ in points], ["aabb minmax [cgal]", "aabb minmax"])

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
        code, _, _ = self.plot()
        self.assertEqual(code, 0)
        names = support.pngs(self.out)
        self.assertIn("bv_tradeoff.png", names)
        # Fit-time curves are split by volume type, one curve per method.
        self.assertIn("bv_obb_fit_3d_double.png", names)
