"""Colours and markers per structure (spatialplots/style.py)."""

import unittest

from . import support
from spatialplots.registry import Registry
from spatialplots.style import FALLBACK, StyleBook

REGISTRY = Registry.from_dict(support.registry_dict(
    [support.suite("knn")],
    [support.structure("kd_tree"),
     support.structure("bvh", family="bvh"), support.structure("bvh_median", family="bvh"),
     support.structure("bvh_obb", family="bvh"),
     support.structure("brute_force", kind="oracle"),
     support.structure("nanoflann", family="nanoflann", kind="peer"),
     support.structure("nanoflann_dynamic", family="nanoflann", kind="peer"),
     support.structure("spatialbench")]))


def hue(colour):
    """The colour's direction in RGB (shades of one hue are scalings towards black/white)."""
    import colorsys
    return round(colorsys.rgb_to_hsv(*colour)[0], 3)


class StyleTest(unittest.TestCase):
    def test_a_structure_keeps_its_style_whatever_else_is_drawn(self):
        few = StyleBook(REGISTRY, ["kd_tree"])
        many = StyleBook(REGISTRY, ["kd_tree", "bvh<aabb>", "brute_force", "nanoflann", "zzz"])
        for label in ("kd_tree", "bvh", "bvh_obb", "brute_force", "nanoflann_dynamic"):
            self.assertEqual(few(label), many(label), label)

    def test_every_structure_has_its_own_style(self):
        book = StyleBook(REGISTRY)
        styles = [book(name) for name in REGISTRY.structures]
        self.assertEqual(len(set(styles)), len(styles))

    def test_a_family_shares_one_hue(self):
        book = StyleBook(REGISTRY)
        self.assertEqual(len({hue(book(name)[0]) for name in ("bvh", "bvh_median", "bvh_obb")}), 1)
        self.assertEqual(hue(book("nanoflann")[0]), hue(book("nanoflann_dynamic")[0]))
        self.assertNotEqual(hue(book("kd_tree")[0]), hue(book("bvh")[0]))

    def test_qualified_labels(self):
        labels = ["bvh<aabb>", "bvh_obb<obb>", "bvh_obb<sphere>", "spatialbench dito",
                  "spatialbench pca", "spatialbench minmax"]
        book = StyleBook(REGISTRY, labels)
        # One volume type: the structure's own style; a second one: another shade of its hue.
        self.assertEqual(book("bvh<aabb>"), book("bvh"))
        self.assertEqual(book("bvh_obb<obb>"), book("bvh_obb"))
        self.assertNotEqual(book("bvh_obb<sphere>"), book("bvh_obb"))
        self.assertEqual(hue(book("bvh_obb<sphere>")[0]), hue(book("bvh_obb")[0]))
        # Curves of one structure named by series params (fit methods): distinct colours,
        # the structure's marker, the same in every book built from the same labels.
        methods = [book(f"spatialbench {m}") for m in ("dito", "pca", "minmax")]
        self.assertEqual(len({colour for colour, _ in methods}), 3)
        self.assertEqual({marker for _, marker in methods}, {book("spatialbench")[1]})
        self.assertEqual(StyleBook(REGISTRY, reversed(labels))("spatialbench pca"), methods[1])

    def test_unknown_labels_and_emphasis(self):
        book = StyleBook(REGISTRY, ["kd_tree"])
        self.assertEqual(book("mystery"), FALLBACK)
        loud = book.emphasised({"bvh"})
        self.assertEqual(loud("bvh<aabb>"), ("black", "*"))
        self.assertEqual(loud("kd_tree"), book("kd_tree"))
        self.assertNotEqual(book("bvh"), ("black", "*"))  # the original is unchanged
