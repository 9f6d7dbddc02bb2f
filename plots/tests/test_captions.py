"""Run captions (spatialplots/figures.py): every figure names the run(s) its rows come from,
and --runs-manifest lists them per figure."""

import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from . import support  # noqa: E402
from .support import row, write_csv  # noqa: E402
from spatialplots import figures  # noqa: E402

REGISTRY = support.registry_dict(
    [support.suite("knn", baseline="kd_tree")],
    [support.structure("kd_tree"), support.structure("brute_force", kind="oracle")])


def runs(*ids):
    return list(ids)


class CaptionTextTest(support.unittest.TestCase):
    def test_one_and_a_few_runs_are_listed(self):
        self.assertEqual(figures.runs_caption(["knn-quick-20261126T120727Z-c88205a"]),
                         "run: knn-quick-20261126T120727Z-c88205a")
        self.assertEqual(figures.runs_caption(["a", "b"]), "runs: a, b")

    def test_many_runs_give_the_count_and_first_and_last(self):
        ids = [f"raycast-full-20261126T13{m:02d}00Z-f2edf77" for m in range(5)]
        self.assertEqual(figures.runs_caption(ids),
                         f"5 runs: {ids[0]} \u2026 {ids[-1]}")

    def test_ids_are_ordered_by_their_timestamp(self):
        rows = ["raycast-quick-20261126T125510Z-c88205a", "raycast-full-20261126T132408Z-f2edf77",
                "raycast-full-20261126T132408Z-f2edf77", ""]
        self.assertEqual(figures.run_ids(rows), ["raycast-quick-20261126T125510Z-c88205a",
                                                 "raycast-full-20261126T132408Z-f2edf77"])

    def test_the_footer_keeps_the_axes_where_they_were(self):
        figure, axis = plt.subplots(figsize=(4, 3))
        figure.suptitle("title")
        before = axis.get_position().y1 * 3.0  # inches from the bottom
        figures.add_footer(figure, "run: x")
        self.assertAlmostEqual(figure.get_figheight(), 3.0 + figures.FOOTER_INCHES)
        self.assertAlmostEqual(axis.get_position().y1 * figure.get_figheight(),
                               before + figures.FOOTER_INCHES)
        self.assertEqual(figure.texts[-1].get_text(), "run: x")
        plt.close(figure)


class CaptionRunTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_every_figure_names_its_runs(self):
        rows = []
        for n in support.NS:
            for structure in ("kd_tree", "brute_force"):
                cells = row(structure=structure, n=n, value=5.0 * n)
                cells[-1] = "knn-quick-20261126T120727Z-c88205a"
                rows.append(cells)
                build = row(structure=structure, n=n, operation="build", params="",
                            metric="build_time", value=5.0 * n, unit="s")
                build[-1] = "knn-full-20261127T000000Z-0000000"
                rows.append(build)
        write_csv(self.results, "knn.csv", rows)
        manifest = os.path.join(self.out, "runs.json")
        code, stdout, stderr = self.plot("--runs-manifest", manifest)
        self.assertEqual(code, 0, stderr)
        with open(manifest) as handle:
            runs_of = json.load(handle)
        self.assertEqual(runs_of["knn_knn_k10_3d_double"], ["knn-quick-20261126T120727Z-c88205a"])
        self.assertEqual(runs_of["knn_build_3d_double"], ["knn-full-20261127T000000Z-0000000"])
        self.assertEqual(sorted(runs_of), sorted(name[:-4] for name in support.pngs(self.out)))
