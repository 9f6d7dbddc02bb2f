"""The BVH trade-off family (spatialplots/families/bvh_tradeoff.py)."""

from . import support
from .support import row
from spatialplots.families import bvh_tradeoff
from spatialplots.registry import Registry

# Which structure is a builder and which a volume type comes from `settings` only.
# (As spatialbench writes them: a bv field, and the builder in every variant's settings.)
REGISTRY = support.registry_dict(
    [support.suite("raycast", baseline="embree")],
    [dict(support.structure("bvh", family="bvh", settings={"builder": "sah", "leaf_size": "4"}), bv="aabb"),
     dict(support.structure("bvh_median", family="bvh", settings={"builder": "median", "leaf_size": "4"}),
          bv="aabb"),
     dict(support.structure("bvh_obb", family="bvh", settings={"builder": "sah", "bv": "obb"}), bv="obb"),
     dict(support.structure("bvh_sphere", family="bvh", settings={"builder": "sah", "bv": "sphere"}),
          bv="sphere"),
     support.structure("embree", kind="peer")])


def bvh_row(structure, bv, n, operation, params, metric, value, unit, validated="true"):
    return row(suite="raycast", structure=structure, workload="sphere", n=n, operation=operation,
               params=params, metric=metric, value=value, unit=unit, validated=validated, bv=bv)


def bvh_rows():
    rows = []
    for n in (1000, 100000):
        for structure, bv, ratio in (("bvh", "aabb", 1.0), ("bvh_obb", "obb", 0.6),
                                     ("bvh_median", "aabb", 1.0)):
            rows.append(bvh_row(structure, bv, n, "build", "", "node_area_ratio", ratio, "ratio"))
            rows.append(bvh_row(structure, bv, n, "build", "", "build_time", 1e-6 * n, "s"))
            rows.append(bvh_row(structure, bv, n, "ray", "rays=incoherent", "time_per_op",
                                2.0 if structure == "bvh_obb" else 1.0, "us"))
            rows.append(bvh_row(structure, bv, n, "ray", "rays=coherent;camera=8x8", "time_per_op",
                                50.0, "ns"))
        # A peer without node tightness takes no part.
        rows.append(bvh_row("embree", "", n, "build", "", "build_time", 1e-7 * n, "s"))
        rows.append(bvh_row("embree", "", n, "ray", "rays=incoherent", "time_per_op", 0.5, "us"))
    # An unvalidated timing drops that point (not the others).
    rows.append(bvh_row("bvh_sphere", "sphere", 100000, "build", "", "node_area_ratio", 1.3, "ratio"))
    rows.append(bvh_row("bvh_sphere", "sphere", 100000, "build", "", "build_time", 0.2, "s", "false"))
    rows.append(bvh_row("bvh_sphere", "sphere", 100000, "ray", "rays=incoherent", "time_per_op", 3.0,
                        "us"))
    return rows


class BvhTradeoffTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def test_bvh_tradeoff_points_take_the_largest_n_and_the_validation_rule(self):
        parsed = self.parsed(bvh_rows(), "raycast.csv")
        data = bvh_tradeoff.bvh_tradeoff_points(parsed, self.registry(), include_unvalidated=False)
        self.assertEqual(list(data), ["sphere"])
        entry = data["sphere"]
        self.assertEqual(entry["n"], 100000)

        def rounded(items):
            return sorted(tuple(round(v, 9) if isinstance(v, float) else v for v in item) for item in items)
        self.assertEqual(rounded(entry["points"]), [("aabb", 1.0, 0.1, 1000.0), ("obb", 0.6, 0.1, 2000.0)])
        self.assertEqual(rounded(entry["builders"]),
                         [("SAH", 1000, 0.001, 1000.0), ("SAH", 100000, 0.1, 1000.0),
                          ("median", 1000, 0.001, 1000.0), ("median", 100000, 0.1, 1000.0)])
        code, _, stderr = self.plot()
        self.assertEqual(code, 0, stderr)
        self.assertIn(bvh_tradeoff.BVH_TRADEOFF_FILE, support.pngs(self.out))

    def test_builder_labels_come_from_settings(self):
        registry = self.registry()
        self.assertEqual(bvh_tradeoff.builder_label(registry, "bvh"), "SAH")
        self.assertEqual(bvh_tradeoff.builder_label(registry, "bvh_median"), "median")
        self.assertIsNone(bvh_tradeoff.builder_label(registry, "embree"))
        # bvh_obb has a builder too, but no other-builder twin: not compared.
        self.assertEqual(bvh_tradeoff.builder_groups(registry, ["bvh", "bvh_median", "bvh_obb", "embree"]),
                         {"bvh": "SAH", "bvh_median": "median"})
        # The provisional form (builder the only setting) works as well.
        plain = support.registry_dict([], [
            support.structure("bvh", settings={"builder": "sah"}),
            support.structure("bvh_median", settings={"builder": "median"}),
            support.structure("bvh_obb", settings={"bv": "obb"})])
        self.assertEqual(bvh_tradeoff.builder_groups(Registry.from_dict(plain), ["bvh", "bvh_median", "bvh_obb"]),
                         {"bvh": "SAH", "bvh_median": "median"})
