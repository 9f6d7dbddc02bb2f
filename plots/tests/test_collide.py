"""The collide family (spatialplots/families/collide.py): boxes, moving boxes, refit decay and
the bounding-volume trade-off of the triangle soup."""

import contextlib
import io

from . import support
from .support import pngs, write_csv
from spatialplots.core import label_of
from spatialplots.family import discover
from spatialplots.families import collide

COLLIDE = support.suite(
    "collide", baseline="cgal_box_intersection",
    targets=[{"metric": "speedup", "structure": "collision_grid", "workload": "boxes",
              "n": 1000000, "value": 5.0, "label": ""},
             {"metric": "steps_per_second", "structure": "", "workload": "moving_boxes",
              "n": 100000, "value": 60.0, "label": ">= 60 steps/s at 1e5"}])
SCENES = support.suite("scenes", stages=["motion", "churn", "update", "collide_pairs",
                                         "collide_narrow_phase", "collide_pair_changes", "raycast",
                                         "nearest", "range"],
                       total_stage="step", once_stages=["build"])
REGISTRY = support.registry_dict(
    [COLLIDE, SCENES],
    [support.structure("collision_grid", complexity=support.GRID),
     support.structure("bvh", family="bvh", settings={"builder": "sah"})]
    + [support.structure(f"bvh_{s}", family="bvh", settings={"strategy": s}) for s in ("refit", "rebuild")]
    + [support.structure(f"bvh_{bv}", family="bvh", settings={"bv": bv}) for bv in ("aabb", "obb", "sphere")]
    + [support.structure(name, kind="peer") for name in ("cgal_box_intersection", "fcl_dynamic_aabb_tree",
                                                         "fcl_sap")])
CGAL = "cgal_box_intersection"


def collide_row(structure, workload, n, operation, metric, value, unit="s", params="overlaps_per_box=2",
                bv="-", validated="true", suite="collide"):
    return [suite, structure, bv, workload, n, 3, "double", operation, params, metric, repr(value), unit,
            validated, "test-run"]


COLLIDE_NS = (1000, 10000)
MOVING = "overlaps_per_box=2;steps=3;speed=side/4"
COLLIDE_FILES = ("collide_boxes.png", "collide_moving.png", "collide_refit_decay.png",
                 "collide_bv_tradeoff.png")


def collide_boxes_rows():
    """build_and_self_pairs times: cgal 10 us per box, collision_grid exactly 5x faster, bvh 2x."""
    rows = []
    for n in COLLIDE_NS:
        for structure, bv, factor in ((CGAL, "-", 1.0), ("collision_grid", "-", 5.0), ("bvh", "aabb", 2.0)):
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
            stepped = structure in ("bvh_refit", "bvh_rebuild")
            bv = "aabb" if stepped else "-"
            rows.append(collide_row(structure, "moving_boxes", n, "build", "time", 1e-6 * n, params=MOVING,
                                    bv=bv))
            rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs", "time", 1e-7 * n,
                                    params=MOVING, bv=bv))
            rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs", "steps_per_second",
                                    1e7 / n, unit="1/s", params=MOVING, bv=bv))
            rows.append(collide_row(structure, "moving_boxes", n, "update_and_self_pairs",
                                    "pairs_changed_per_step", 0.1 * n, unit="count", params=MOVING, bv=bv))
            if stepped:
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


class CollidePlotTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_suite_is_claimed_and_dash_means_no_bv(self):
        families = {f.name: f for f in discover()}
        self.assertIn("collide", families["collide"].suites)
        self.assertTrue(families["collide"].exclusive)
        parsed = self.parsed(collide_boxes_rows(), "collide.csv")
        grid = [r for r in parsed if r.structure == "collision_grid"]
        self.assertTrue(grid)
        self.assertEqual({r.bv for r in grid}, {""})
        self.assertEqual(label_of(grid[0]), "collision_grid")

    def test_speedup_is_baseline_time_over_time(self):
        series = {(CGAL, True): {1000: 10.0, 10000: 100.0},
                  ("collision_grid", True): {1000: 2.0, 10000: 20.0},
                  ("bvh<aabb>", True): {1000: 4.0, 100000: 1.0},  # 1e5: no cgal time, no ratio
                  ("fcl_sap", False): {10000: 400.0}}
        ratios = collide.speedups(series, CGAL)
        self.assertEqual(ratios, {("collision_grid", True): {1000: 5.0, 10000: 5.0},
                                  ("bvh<aabb>", True): {1000: 2.5},
                                  ("fcl_sap", False): {10000: 0.25}})
        self.assertEqual(collide.speedups({("bvh", True): {1000: 1.0}}, CGAL), {})

    def test_speedup_from_csv_takes_medians(self):
        rows = collide_boxes_rows()
        # Two more runs of cgal at 1e3: the median (the original) is kept.
        rows.append(collide_row(CGAL, "boxes", 1000, "build_and_self_pairs", "time", 1.0))
        rows.append(collide_row(CGAL, "boxes", 1000, "build_and_self_pairs", "time", 1e-9))
        # An unvalidated, absurdly fast grid timing is not drawn.
        rows.append(collide_row("collision_grid", "boxes", 1000, "build_and_self_pairs", "time", 1e-12,
                                validated="false"))
        parsed = self.parsed(rows, "collide.csv")
        with contextlib.redirect_stderr(io.StringIO()):
            data = collide.collide_boxes_series(parsed, include_unvalidated=False)
        self.assertEqual(list(data), [("overlaps_per_box=2", 3, "double")])
        ratios = collide.speedups(collide.median_points(data[("overlaps_per_box=2", 3, "double")]),
                                  self.registry().baseline("collide"))
        self.assertEqual(sorted(ratios), [("bvh<aabb>", True), ("collision_grid", True)])
        for n in COLLIDE_NS:
            self.assertAlmostEqual(ratios[("collision_grid", True)][n], 5.0, delta=1e-9)
            self.assertAlmostEqual(ratios[("bvh<aabb>", True)][n], 2.0, delta=1e-9)

    def test_refit_decay_and_moving_series(self):
        parsed = self.parsed(collide_moving_rows(), "collide.csv")
        decay = collide.refit_decay_series(parsed, include_unvalidated=False)
        self.assertEqual(sorted(decay), [(n, MOVING) for n in COLLIDE_NS])
        quality = decay[(1000, MOVING)]["quality"]
        self.assertEqual(quality[("bvh_refit<aabb>", True)], {1: 45.0, 2: 50.0, 3: 55.0})
        self.assertEqual(quality[("bvh_rebuild<aabb>", True)], {1: 40.0, 2: 40.0, 3: 40.0})
        self.assertAlmostEqual(decay[(1000, MOVING)]["time"][("bvh_rebuild<aabb>", True)][2], 0.1)  # ms
        groups, bars, changed = collide.collide_moving_bars(parsed, include_unvalidated=False)
        self.assertEqual(groups, [(n, MOVING) for n in COLLIDE_NS])
        self.assertAlmostEqual(bars[("collision_grid", True)][(10000, MOVING)], 1000.0)
        self.assertAlmostEqual(changed[(10000, MOVING)], 1000.0)

    def test_targets_come_from_the_registry(self):
        registry = self.registry()
        speed = collide.targets(registry, "collide", collide.SPEEDUP, "boxes")
        self.assertEqual([(t.structure, t.value, t.n) for t in speed], [("collision_grid", 5.0, 1000000)])
        self.assertEqual(collide.targets(registry, "collide", collide.SPEEDUP, "moving_boxes"), [])
        (steps,) = collide.targets(registry, "collide", collide.STEPS_PER_SECOND, "moving_boxes")
        self.assertEqual(collide.target_text(steps, "unused"), "target: >= 60 steps/s at 1e5")
        self.assertEqual(collide.target_text(speed[0], "collision_grid \u2265 5x at n=1e6"),
                         "target: collision_grid \u2265 5x at n=1e6")

    def test_all_figures_are_written(self):
        write_csv(self.results, "collide.csv",
                  collide_boxes_rows() + collide_moving_rows() + collide_triangle_rows())
        write_csv(self.results, "scenes.csv", scenes_rows())
        code, stdout, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        # Only the dedicated figures: no generic complexity curves of these suites.
        self.assertEqual(pngs(self.out), sorted(COLLIDE_FILES + ("scenes.png", "collide_summary.png",
                                                                  "scenes_summary.png")))
        for name in pngs(self.out):
            self.assert_png(name)
            self.assertIn(name, stdout)
        self.assertNotIn("skip collide", stderr)

    def test_missing_workloads_are_skipped_with_a_note(self):
        write_csv(self.results, "collide.csv", collide_boxes_rows())
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertEqual(pngs(self.out), ["collide_boxes.png", "collide_summary.png"])
        for name in COLLIDE_FILES[1:]:
            self.assertIn(f"skip {name}", stderr)

    def test_only_moving_boxes_and_no_baseline(self):
        rows = collide_moving_rows() + [r for r in collide_boxes_rows() if r[1] != CGAL]
        write_csv(self.results, "collide.csv", rows)
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertEqual(pngs(self.out), ["collide_boxes.png", "collide_moving.png",
                                          "collide_refit_decay.png", "collide_summary.png"])
        self.assertIn("no speed-up panel", stderr)
        self.assertIn("skip collide_bv_tradeoff.png", stderr)

    def test_unvalidated_moving_rows_are_skipped_unless_asked(self):
        rows = [r[:12] + ["false"] + r[13:] for r in collide_moving_rows()]
        write_csv(self.results, "collide.csv", rows)
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertIn("unvalidated", stderr)
        self.assertIn("skip collide_moving.png", stderr)
        # Tree quality is not a timing: the decay figure still shows it.
        self.assertEqual(pngs(self.out), ["collide_refit_decay.png"])
        code, _, stderr = self.plot("--include-unvalidated")
        self.assertEqual(code, 0, stderr)
        self.assertIn("collide_moving.png", pngs(self.out))

    def test_bv_points(self):
        parsed = self.parsed(collide_triangle_rows(), "collide.csv")
        points = collide.collide_bv_points(parsed, self.registry(), include_unvalidated=False)
        self.assertEqual(list(points), [("soup", 2000)])
        by_label = {p[0]: p[1:] for p in points[("soup", 2000)]}
        self.assertEqual(sorted(by_label), ["aabb", "obb", "sphere"])
        self.assertEqual(by_label["obb"], (1500.0, 0.8, 2e-3, 4e-3))

    def test_bv_points_label_by_the_registry_bv(self):
        # spatialbench's own registry names the aabb variant "bvh" (bv field "aabb"); a
        # structure used with another volume type than its own keeps its full label.
        data = dict(REGISTRY, structures=REGISTRY["structures"] + [
            dict(support.structure("bvh_plain", family="bvh"), bv="aabb")])
        support.write_registry(self.results, data)
        rows = [r for r in collide_triangle_rows() if r[1] == "bvh_aabb"]
        rows = [["collide", "bvh_plain"] + r[2:] for r in rows] + [
            ["collide", "bvh_obb", "sphere"] + r[3:] for r in rows]
        points = collide.collide_bv_points(self.parsed(rows, "collide.csv"), self.registry(), False)
        self.assertEqual(sorted(p[0] for p in points[("soup", 2000)]), ["aabb", "bvh_obb<sphere>"])


def scenes_rows():
    rows = []
    params = "steps=100;strategy=automatic;filter=exact"
    for scene, stages in (("boxes_100k", ("motion", "update", "collide_pairs", "collide_pair_changes")),
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
