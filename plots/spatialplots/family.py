"""Figure families: how a module under spatialplots/families/ says what it draws.

A family module registers its drawing function with the decorator:

    @figure_family("raycast", suites=("raycast",), order=30)
    def draw(ctx):
        '''What the figure shows.'''
        ...
        return [paths of the PNGs written]

`suites` are the suites whose rows the family receives (ctx.rows); None means every suite that
no `exclusive` family claims.  `exclusive=True` keeps the family's suites away from the
suites=None families (the collide and scenes suites get only their own figures).  A family
with suites is not called when none of its suites has rows.  `order` only fixes the order in
which the families run (and so the order of the "wrote" lines on stdout).

discover() imports every module of the families package with pkgutil, so adding a family is
adding a module; nothing lists them by name.
"""

import importlib
import pkgutil
from dataclasses import dataclass
from typing import Callable, Optional, Tuple

_REGISTERED = []


@dataclass(frozen=True)
class Family:
    name: str
    draw: Callable
    module: str
    suites: Optional[Tuple[str, ...]] = None
    exclusive: bool = False
    order: int = 100


@dataclass
class Context:
    """What a family's draw(ctx) gets."""
    rows: list  # the rows of the family's suites (registry-checked, validation not yet applied)
    registry: object  # spatialplots.registry.Registry
    styles: object  # spatialplots.style.StyleBook
    out_dir: str
    include_unvalidated: bool


def figure_family(name, suites=None, exclusive=False, order=100):
    """Decorator registering draw(ctx) -> [PNG paths] as the figure family `name`."""
    def register(draw):
        family = Family(name=name, draw=draw, module=draw.__module__,
                        suites=tuple(suites) if suites is not None else None,
                        exclusive=exclusive, order=order)
        _REGISTERED[:] = [f for f in _REGISTERED if (f.module, f.name) != (family.module, name)]
        _REGISTERED.append(family)
        return draw
    return register


def discover(package="spatialplots.families"):
    """Import every module of `package` (a dotted name or a module) and return the families
    registered by them, sorted by (order, name)."""
    if isinstance(package, str):
        package = importlib.import_module(package)
    prefix = package.__name__ + "."
    for info in pkgutil.iter_modules(package.__path__, prefix):
        importlib.import_module(info.name)
    found = [f for f in _REGISTERED if f.module.startswith(prefix)]
    return sorted(found, key=lambda f: (f.order, f.name))


def rows_for(family, rows, families):
    """The rows `family` draws: those of its suites, or of every suite no exclusive family
    among `families` claims."""
    if family.suites is not None:
        return [row for row in rows if row.suite in family.suites]
    claimed = {s for f in families if f.exclusive and f.suites for s in f.suites}
    return [row for row in rows if row.suite not in claimed]
