"""The summary family (spatialplots/families/summary.py): structures ranked over all workloads
by their time relative to the best in each case."""

import csv
import os

import matplotlib

matplotlib.use("Agg")

from . import support  # noqa: E402
from .support import row, write_csv  # noqa: E402
from spatialplots.families import summary  # noqa: E402

REGISTRY = support.registry_dict(
    [support.suite("knn", baseline="kd_tree"), support.suite("raycast"),
     support.suite("collide"), support.suite("scenes")],
    [support.structure("kd_tree"), support.structure("nanoflann", kind="peer"),
     support.structure("brute_force", kind="oracle"),
     support.structure("bvh", family="bvh", settings={"builder": "sah"}),
     support.structure("bvh_obb", family="bvh", settings={"builder": "sah", "bv": "obb"}),
     support.structure("bvh_median", family="bvh", settings={"builder": "median"}),
     support.structure("embree", kind="peer")])

KNN = summary.SUMMARIES[0]
RAYCAST = next(s for s in summary.SUMMARIES if s.suite == "raycast")
SCENES = next(s for s in summary.SUMMARIES if s.suite == "scenes")
BV = next(s for s in summary.SUMMARIES if s.suite == "bv")


def knn_rows():
    """Two workloads, k=10 and k=1, at n=1e5: kd_tree 10 ns, nanoflann 20 and 40 ns, brute
    force 1000 ns (uniform) and 3000 ns (clusters); k=1 times are halved.  Brute force also
    appears at n=1e4 only on the line workload, where the largest n is 1e5."""
    rows = []
    for workload, slow in (("uniform", 1.0), ("clusters", 2.0)):
        for params, scale in (("k=10", 1.0), ("k=1", 0.5)):
            for structure, time in (("kd_tree", 10.0), ("nanoflann", 20.0 * slow),
                                    ("brute_force", 1000.0 + 2000.0 * (slow - 1.0))):
                rows.append(row(structure=structure, workload=workload, n=100000,
                                params=params, value=time * scale))
    for params in ("k=10", "k=1"):
        rows.append(row(structure="kd_tree", workload="line", n=100000, params=params, value=5.0))
        rows.append(row(structure="nanoflann", workload="line", n=100000, params=params,
                        value=10.0))
        rows.append(row(structure="kd_tree", workload="line", n=10000, params=params, value=2.0))
        rows.append(row(structure="brute_force", workload="line", n=10000, params=params,
                        value=200.0))
    return rows


def by_case(points, entry):
    return {(p.case[0], p.variant): p for p in points[entry]}


class SummaryTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def summarise(self, rows, which=KNN):
        return summary.summarise(self.parsed(rows), which, self.registry())

    def test_ratios_are_times_over_the_best_in_each_case(self):
        points, used = self.summarise(knn_rows())
        nano = by_case(points, "nanoflann")
        self.assertAlmostEqual(nano[("uniform", "k=10")].ratio, 2.0)
        self.assertAlmostEqual(nano[("clusters", "k=10")].ratio, 4.0)
        self.assertAlmostEqual(nano[("clusters", "k=1")].ratio, 4.0)
        self.assertTrue(all(p.ratio == 1.0 for p in points["kd_tree"]))
        brute = by_case(points, "brute_force")
        self.assertAlmostEqual(brute[("uniform", "k=10")].ratio, 100.0)
        self.assertAlmostEqual(brute[("clusters", "k=1")].ratio, 300.0)
        self.assertEqual(len(points["kd_tree"]), 6)  # 3 workloads x 2 values of k
        self.assertEqual(len(used), len(knn_rows()))

    def test_ranking_by_median_ratio(self):
        points, _ = self.summarise(knn_rows())
        self.assertEqual(summary.ranking(points), ["kd_tree", "nanoflann", "brute_force"])

    def test_a_structure_missing_at_the_largest_n_is_compared_at_its_own(self):
        points, _ = self.summarise(knn_rows())
        line = by_case(points, "brute_force")[("line", "k=10")]
        self.assertEqual(line.n, 10000)
        self.assertTrue(line.below_largest)
        self.assertAlmostEqual(line.ratio, 100.0)  # 200 / kd_tree's 2 at n=1e4
        self.assertFalse(by_case(points, "nanoflann")[("line", "k=10")].below_largest)
        self.assertEqual(by_case(points, "kd_tree")[("line", "k=10")].n, 100000)

    def test_repeated_runs_are_pooled_by_their_median(self):
        rows = []
        for run, bvh in (("run-a", 30.0), ("run-b", 10.0), ("run-c", 20.0), ("run-d", 1000.0),
                         ("run-e", 25.0)):
            for structure, time in (("bvh", bvh), ("embree", 10.0)):
                cells = row(suite="raycast", structure=structure, workload="sphere",
                            n=1000000, operation="ray", params="rays=incoherent", value=time,
                            bv="aabb" if structure == "bvh" else "")
                cells[-1] = run
                rows.append(cells)
        points, used = self.summarise(rows, RAYCAST)
        (point,) = points["bvh<aabb>"]
        self.assertAlmostEqual(point.ratio, 2.5)  # median(10, 20, 25, 30, 1000) / 10
        self.assertEqual(len({r.run_id for r in used}), 5)

    def test_unvalidated_and_unchecked_rows_are_left_out(self):
        rows = knn_rows()
        # nanoflann's k=10 uniform time is unvalidated; a faster brute force has check=none.
        rows.append(row(structure="nanoflann", workload="uniform", n=100000, value=1.0,
                        validated="false"))
        header = support.HEADER + ["check"]
        checked = [cells + ["oracle:all"] for cells in rows]
        checked.append(row(structure="brute_force", workload="clusters", n=100000,
                           value=0.5) + ["none"])
        write_csv(self.results, "knn.csv", checked, header=header)
        from spatialplots.io import read_results
        parsed = read_results(self.results, self.registry())
        points, used = summary.summarise(parsed, KNN, self.registry())
        self.assertAlmostEqual(by_case(points, "nanoflann")[("uniform", "k=10")].ratio, 2.0)
        self.assertAlmostEqual(by_case(points, "brute_force")[("clusters", "k=10")].ratio, 300.0)
        self.assertTrue(all(r.validated for r in used))
        self.assertFalse(any(r.check == "none" for r in used))

    def test_rates_rank_higher_as_better(self):
        rows = []
        for scene, rates in (("a", {"kd_tree": 100.0, "bvh": 50.0}),
                             ("b", {"kd_tree": 40.0, "bvh": 80.0, "brute_force": 8.0})):
            for structure, rate in rates.items():
                rows.append(row(suite="scenes", structure=structure, workload=scene, n=1000,
                                operation="step", params="steps=30", metric="steps_per_second",
                                value=rate, unit="1/s"))
        points, _ = self.summarise(rows, SCENES)
        self.assertAlmostEqual(by_case(points, "bvh")[("a", "scene")].ratio, 2.0)
        self.assertAlmostEqual(by_case(points, "kd_tree")[("b", "scene")].ratio, 2.0)
        self.assertAlmostEqual(by_case(points, "brute_force")[("b", "scene")].ratio, 10.0)
        self.assertEqual(summary.ranking(points)[-1], "brute_force")

    def test_volume_summary_ranks_volume_types_of_sah_bvhs_only(self):
        rows = []
        for structure, bv, time in (("bvh", "aabb", 10.0), ("bvh_obb", "obb", 30.0),
                                    ("bvh_median", "aabb", 5.0), ("embree", "", 1.0)):
            rows.append(row(suite="raycast", structure=structure, workload="sphere", n=1000,
                            operation="ray", params="rays=incoherent", value=time, bv=bv))
        points, _ = self.summarise(rows, BV)
        self.assertEqual(sorted(points), ["aabb", "obb"])
        self.assertAlmostEqual(points["obb"][0].ratio, 3.0)

    def test_figures_are_written_with_their_runs(self):
        write_csv(self.results, "knn.csv", knn_rows())
        code, stdout, stderr = self.plot("--families", "summary", "--runs-manifest",
                                         os.path.join(self.out, "runs.json"))
        self.assertEqual(code, 0, stderr)
        self.assert_png("knn_summary.png")
        self.assertEqual(support.pngs(self.out), ["knn_summary.png"])
        with open(os.path.join(self.out, "runs.json")) as handle:
            self.assertIn('"knn_summary": [\n  "test-run"\n ]', handle.read())

    def test_too_few_structures_is_noted(self):
        write_csv(self.results, "knn.csv", [row(structure="kd_tree", n=n) for n in support.NS])
        code, _, stderr = self.plot("--families", "summary")
        self.assertEqual(code, 0, stderr)
        self.assertIn("skip knn_summary.png", stderr)
        self.assertEqual(support.pngs(self.out) if os.path.isdir(self.out) else [], [])


if __name__ == "__main__":
    import unittest
    unittest.main()
