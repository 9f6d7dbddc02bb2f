"""Colours and markers per structure, the same in every figure.

The style of a structure depends only on the registry, not on which rows a figure happens to
hold: each structure `family` (in registry order) gets one hue, and the variants of a family
(its structures, in registry order: bvh, bvh_median, bvh_obb, ...) get shades of that hue
and different markers, so every structure name has its own style.  Families also start at
different markers, so that two similar hues still differ in shape.

Two kinds of label qualify a structure:
* "bvh<obb>" (a volume type): the structure's style; when one structure appears with several
  volume types, each further one gets the next shade/marker of the family.
* "spatialbench dito" (the values of a suite's series_params, e.g. bv fit methods): these are
  not structures but curves of one structure that a figure must tell apart, so each such label
  gets its own colour from the palette (by its rank among all such labels of the results),
  and keeps the structure's marker.
"""

import matplotlib.pyplot as plt

from .core import structure_of

MARKERS = "osD^v<>pPhX*"
# Shade steps: negative darkens towards black, positive lightens towards white.
SHADES = (0.0, -0.3, 0.35, -0.5, 0.55, -0.15, 0.2)
FALLBACK = ("dimgrey", "o")  # a label that names no registry structure (e.g. a vs= peer)


def _palette():
    """20 hues: tab10, then the light halves of tab20."""
    strong = [plt.get_cmap("tab10")(i)[:3] for i in range(10)]
    light = [plt.get_cmap("tab20")(2 * i + 1)[:3] for i in range(10)]
    return strong + light


PALETTE = _palette()


def shade(rgb, step):
    if step < 0:
        return tuple(c * (1.0 + step) for c in rgb)
    return tuple(c + (1.0 - c) * step for c in rgb)


class StyleBook:
    """style(label) -> (colour, marker).  labels: every label the figures will draw, so that
    several qualifiers of one structure can be told apart."""

    def __init__(self, registry, labels=()):
        self._base = {}  # structure -> (hue, family index, index in family, family size)
        for f, members in enumerate(registry.families().values()):
            for j, name in enumerate(members):
                self._base[name] = (PALETTE[f % len(PALETTE)], f, j, len(members))
        known = sorted(label for label in set(labels)
                       if label != structure_of(label) and structure_of(label) in self._base)
        volumes = {}
        for label in known:
            if "<" in label:
                volumes.setdefault(structure_of(label), []).append(label)
        self._qualifier_index = {label: k for found in volumes.values()
                                 for k, label in enumerate(found)}
        self._series_index = {label: i for i, label in
                              enumerate(label for label in known if "<" not in label)}
        self._overrides = {}

    def _structure_style(self, structure, qualifier=0):
        hue, family, index, family_size = self._base[structure]
        index += qualifier * family_size
        return shade(hue, SHADES[index % len(SHADES)]), MARKERS[(family + index) % len(MARKERS)]

    def __call__(self, label):
        structure = structure_of(label)
        if structure in self._overrides:
            return self._overrides[structure]
        if structure not in self._base:
            return FALLBACK
        if label in self._series_index:
            colour = PALETTE[self._series_index[label] % len(PALETTE)]
            return colour, self._structure_style(structure)[1]
        return self._structure_style(structure, self._qualifier_index.get(label, 0))

    def emphasised(self, structures, style=("black", "*")):
        """A copy in which every label of the given structures is drawn in `style` (the
        structures a target line is about)."""
        book = StyleBook.__new__(StyleBook)
        book.__dict__.update(self.__dict__)
        book._overrides = dict(self._overrides, **{s: style for s in structures})
        return book
