"""The ratios family (spatialplots/families/ratios.py): baseline time / peer time."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from . import support  # noqa: E402
from .support import NS, row, write_csv  # noqa: E402
from spatialplots.families import ratios  # noqa: E402
from spatialplots.style import StyleBook  # noqa: E402

REGISTRY = support.registry_dict(
    [support.suite("knn", baseline="kd_tree"), support.suite("structures")],
    [support.structure("kd_tree"), support.structure("nanoflann", kind="peer"),
     support.structure("brute_force", kind="oracle")])


def ratio_rows(suite="knn"):
    rows = []
    for n in NS:
        rows.append(row(suite=suite, structure="nanoflann", n=n, metric="time_ratio", value=1.2,
                        unit="ratio"))
        # The peer named in params, the baseline in structure.
        rows.append(row(suite=suite, structure="kd_tree", n=n, params="k=10;vs=brute_force",
                        metric="time_ratio", value=0.01, unit="ratio"))
    return rows


class RatiosTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_peers_and_groups(self):
        panels = ratios.ratio_panels(self.parsed(ratio_rows()), "knn")
        by_peer = panels[("uniform", 3, "double")]
        self.assertEqual(sorted(by_peer), ["brute_force", "nanoflann"])
        self.assertEqual(by_peer["brute_force"][("knn", "k=10")][NS[-1]], [0.01])

    def test_figure_names_the_registry_baseline(self):
        write_csv(self.results, "knn.csv", ratio_rows())
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assert_png("knn_ratios.png")
        figure, axis = plt.subplots()
        panels = ratios.ratio_panels(self.parsed(ratio_rows()), "knn")
        ratios.draw_ratio_panel(axis, ("uniform", 3, "double"), panels[("uniform", 3, "double")],
                                StyleBook(self.registry()), "kd_tree")
        self.assertEqual(axis.get_ylabel(), "kd_tree time / peer time (ratio)")
        self.assertEqual(axis.get_yscale(), "log")  # 0.01 .. 1.2 spans more than a decade
        plt.close(figure)

    def test_suite_without_baseline_is_noted(self):
        write_csv(self.results, "structures.csv", ratio_rows("structures"))
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assert_png("structures_ratios.png")
        self.assertIn("has no baseline", stderr)
