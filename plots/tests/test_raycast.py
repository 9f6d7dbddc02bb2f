"""The raycast family (spatialplots/families/raycast.py): time per ray against n."""

import contextlib
import io
import math
import os

from . import support
from .support import NS, row, write_csv
from spatialplots.core import fit_exponent
from spatialplots.families import raycast

REGISTRY = support.registry_dict(
    [support.suite("raycast", baseline="embree")],
    [support.structure("embree", kind="peer"), support.structure("cgal_aabb_tree", kind="peer"),
     support.structure("broken")])


def raycast_rows():
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


class RaycastPlotTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_series_follow_the_validation_rule_and_take_medians(self):
        parsed = self.parsed(raycast_rows(), "raycast.csv")
        with contextlib.redirect_stderr(io.StringIO()):
            series, unit = raycast.raycast_series(parsed)
        self.assertEqual(unit, "s")  # ns and us rows mixed: drawn in seconds
        self.assertEqual(sorted(series), ["rays=coherent;camera=128x128", "rays=incoherent"])
        keys = series["rays=incoherent"]
        self.assertNotIn(("broken", "sphere", False), keys)
        self.assertAlmostEqual(keys[("cgal_aabb_tree", "soup", True)][10000], 1e-9 * 10000)
        self.assertAlmostEqual(keys[("embree", "real:bunny.obj", True)][69666], 0.3e-6)
        # Exponents: linear for cgal here, flat-ish (log n) for embree.
        cgal = keys[("cgal_aabb_tree", "sphere", True)]
        self.assertAlmostEqual(fit_exponent(sorted(cgal), [cgal[n] for n in sorted(cgal)]),
                               1.0, delta=1e-9)

    def test_raycast_figure_is_written(self):
        write_csv(self.results, "raycast.csv", raycast_rows())
        code, stdout, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        names = support.pngs(self.out)
        self.assertIn(raycast.RAYCAST_FILE, names)
        self.assertIn("raycast_ray_raysincoherent_3d_double.png", names)  # the generic curves too
        self.assertIn("unvalidated", stderr)
        with open(os.path.join(self.out, raycast.RAYCAST_FILE), "rb") as handle:
            self.assertEqual(handle.read(8), support.PNG_MAGIC)
