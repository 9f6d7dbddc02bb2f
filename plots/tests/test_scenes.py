"""The scenes family (spatialplots/families/scenes.py): stacked per-stage step times."""

from . import support
from .support import pngs, write_csv
from .test_collide import SCENES, scenes_rows
from spatialplots.family import discover
from spatialplots.families import scenes

REGISTRY = support.registry_dict(
    [SCENES],
    [support.structure("collision_grid", complexity=support.GRID),
     support.structure("bvh", family="bvh", settings={"builder": "sah"})])
PARAMS = "steps=100;strategy=automatic;filter=exact"


class ScenesTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_suite_is_claimed_by_its_runner_name(self):
        families = {f.name: f for f in discover()}
        self.assertEqual(families["scenes"].suites, ("scenes",))  # the runner's suite name
        self.assertNotIn("scene", families["scenes"].suites)
        self.assertTrue(families["scenes"].exclusive)

    def test_scene_stage_times(self):
        parsed = self.parsed(scenes_rows(), name="scenes.csv")
        times, rates = scenes.scene_stage_times(parsed, self.registry().suite("scenes"),
                                                include_unvalidated=False)
        self.assertEqual(sorted(times), [("boxes_100k", 100000), ("queries", 100000)])
        grid = times[("queries", 100000)][("collision_grid", PARAMS, True)]
        self.assertNotIn("build", grid)  # once per scene, not a stage
        self.assertAlmostEqual(grid["churn"], 2.0)  # ms
        self.assertAlmostEqual(grid["step"], 23.0)
        self.assertAlmostEqual(rates[("queries", 100000)][("collision_grid", PARAMS, True)], 1000.0 / 23.0)
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertEqual(pngs(self.out), ["scenes.png", "scenes_summary.png"])

    def test_once_stages_come_from_the_registry(self):
        data = support.registry_dict([dict(SCENES, once_stages=[])], REGISTRY["structures"])
        support.write_registry(self.results, data)
        parsed = self.parsed(scenes_rows(), name="scenes.csv")
        times, _ = scenes.scene_stage_times(parsed, self.registry().suite("scenes"),
                                            include_unvalidated=False)
        self.assertAlmostEqual(times[("queries", 100000)][("collision_grid", PARAMS, True)]["build"], 50.0)

    def test_no_stage_rows_is_a_note(self):
        write_csv(self.results, "scenes.csv", [r for r in scenes_rows() if r[7] in ("build", "step")])
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertIn("skip scenes.png", stderr)
        self.assertEqual(pngs(self.out), ["scenes_summary.png"])  # steps/s rows are there
