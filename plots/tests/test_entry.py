"""The entry point (plots/plot_results.py -> spatialplots.cli): discovery of the figure
families, the command line, atomic writes and the validation rule end to end."""

import os
import pkgutil
import subprocess
import sys
import tempfile
import textwrap

from . import support
from .support import NS, row, write_csv
import spatialplots.families
from spatialplots import family as family_module

REGISTRY = support.registry_dict(
    [support.suite("knn", baseline="kd_tree")],
    [support.structure("kd_tree"), support.structure("brute_force", kind="oracle"),
     support.structure("nanoflann", kind="peer")])

PROBE = textwrap.dedent('''
    """A throwaway figure family: records that it ran, claims the knn suite exclusively."""
    import os
    from spatialplots.family import figure_family

    @figure_family("probe", suites=("knn",), exclusive=True, order=999)
    def draw(ctx):
        with open(os.path.join(ctx.out_dir, "probe.txt"), "w") as handle:
            handle.write(f"{len(ctx.rows)} {sorted({r.suite for r in ctx.rows})}")
        return []
''')


def known_exponent_rows():
    """time = 5 n exactly for every timing; recall and ratio rows for the other two plots."""
    rows = support.linear_timing_rows()
    for n in NS:
        for eps in (0, 0.5, 1, 2):
            params = f"k=10;eps={eps}"
            rows.append(row(n=n, operation="approx_knn", params=params,
                            value=5.0 * n / (1 + eps)))
            rows.append(row(n=n, operation="approx_knn", params=params, metric="recall",
                            value=1.0 - 0.1 * eps, unit="ratio"))
        rows.append(row(structure="nanoflann", n=n, metric="time_ratio", value=1.2, unit="ratio"))
    return rows


class DiscoveryTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_every_family_module_is_discovered(self):
        modules = {info.name for info in pkgutil.iter_modules(spatialplots.families.__path__)}
        found = family_module.discover()
        self.assertEqual({f.module.rsplit(".", 1)[1] for f in found}, modules)
        for name in ("complexity", "recall", "ratios", "raycast", "bv_tradeoff", "bvh_tradeoff",
                     "collide", "scenes", "summary"):
            self.assertIn(name, modules)
        for family in found:
            self.assertTrue(family.draw.__doc__, f"{family.name} has no docstring")

    def test_a_new_family_module_is_found_and_run(self):
        write_csv(self.results, "knn.csv", known_exponent_rows())
        with tempfile.TemporaryDirectory() as extra:
            with open(os.path.join(extra, "zz_probe.py"), "w") as handle:
                handle.write(PROBE)
            spatialplots.families.__path__.append(extra)
            try:
                code, _, stderr = self.plot()
            finally:
                spatialplots.families.__path__.remove(extra)
                sys.modules.pop("spatialplots.families.zz_probe", None)
                family_module._REGISTERED[:] = [f for f in family_module._REGISTERED
                                                if not f.module.endswith(".zz_probe")]
        self.assertEqual(code, 0, stderr)
        with open(os.path.join(self.out, "probe.txt")) as handle:
            self.assertEqual(handle.read(), f"{len(known_exponent_rows())} ['knn']")
        # It claimed knn exclusively: the generic families drew nothing of it (the summary
        # family names its suites, so it still ranks them).
        self.assertEqual(support.pngs(self.out), ["knn_summary.png"])
        self.assertNotIn("probe", [f.name for f in family_module.discover()])

    def test_a_family_package_can_be_given(self):
        write_csv(self.results, "knn.csv", known_exponent_rows())
        with tempfile.TemporaryDirectory() as root:
            os.makedirs(os.path.join(root, "probe_families"))
            open(os.path.join(root, "probe_families", "__init__.py"), "w").close()
            with open(os.path.join(root, "probe_families", "only.py"), "w") as handle:
                handle.write(PROBE)
            sys.path.insert(0, root)
            try:
                code, _, stderr = self.plot_with("probe_families")
            finally:
                sys.path.remove(root)
                for name in ("probe_families", "probe_families.only"):
                    sys.modules.pop(name, None)
        self.assertEqual(code, 0, stderr)
        self.assertTrue(os.path.isfile(os.path.join(self.out, "probe.txt")))
        self.assertIn("0 figure(s) written", stderr)

    def plot_with(self, package):
        return support.run_main("--results", self.results, "--out", self.out,
                                families_package=package)


class PlotFilesTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_pngs_are_created(self):
        write_csv(self.results, "knn.csv", known_exponent_rows())
        code, stdout, _ = self.plot()
        self.assertEqual(code, 0)
        for name in ("knn_knn_k10_3d_double.png", "knn_build_3d_double.png",
                     "knn_recall_vs_time_uniform_3d_double.png", "knn_ratios.png"):
            self.assert_png(name)
        # Atomic writes leave no temporary files behind.
        self.assertEqual([name for name in os.listdir(self.out) if not name.endswith(".png")], [])
        self.assertIn("knn_knn_k10_3d_double.png", stdout)

    def test_unvalidated_timings_are_skipped_unless_asked(self):
        write_csv(self.results, "knn.csv",
                  [row(n=n, value=5.0 * n, validated="false") for n in NS])
        code, _, stderr = self.plot()
        self.assertEqual(code, 0)
        self.assertIn("unvalidated", stderr)
        self.assertEqual(support.pngs(self.out), [])
        code, _, _ = self.plot("--include-unvalidated")
        self.assertEqual(code, 0)
        self.assert_png("knn_knn_k10_3d_double.png")

    def test_command_line(self):
        write_csv(self.results, "knn.csv", known_exponent_rows())
        done = subprocess.run([sys.executable, support.SCRIPT, "--results", self.results,
                               "--out", self.out], capture_output=True, text=True, timeout=300)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assert_png("knn_build_3d_double.png")
