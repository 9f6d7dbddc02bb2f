"""Collisions (collide*.csv): static boxes (build + all pairs) at the largest n, every structure
against CGAL's box_intersection_d (the suite's baseline); moving boxes (steps per second, every
structure and the BVH update strategies)."""

from .. import quotes
from ..latex import key_part, name, ref, tabular

SUITE = "collide"
STATIC = dict(suite=SUITE, workload="boxes", operation="build_and_self_pairs", metric="time")
MOVING = dict(suite=SUITE, workload="moving_boxes", operation="update_and_self_pairs",
              metric="steps_per_second")


def baseline(ctx):
    for entry in ctx.registry.get("suites", []):
        if entry.get("name") == SUITE and entry.get("baseline"):
            return entry["baseline"]
    return "cgal_box_intersection"


def static(ctx):
    n = ctx.rows.largest_n(**STATIC)
    if n is None:
        ctx.book.missing("collide.static.n", "boxes rows")
        return
    quotes.size(ctx.book, "collide.static.n", ctx.rows.find(n=n, **STATIC))
    base = ctx.rows.find(n=n, structure=baseline(ctx), **STATIC)
    body = []
    for structure, rows in sorted(ctx.rows.by("structure", n=n, **STATIC).items(),
                                  key=lambda item: min(r.value for r in item[1])):
        key = f"collide.static.{key_part(structure)}"
        quotes.time(ctx.book, key + ".time", rows)
        quotes.ratio(ctx.book, key + ".speedup", [base, rows], "ratio")
        body.append([name(structure), ref(key + ".time"), ref(key + ".speedup")])
    ctx.table("collide_static.tex", tabular("lrr", ["structure", "build + all pairs",
                                                    f"speed-up over {name(baseline(ctx))}"], body))


def moving(ctx):
    n = ctx.rows.largest_n(**MOVING)
    if n is None:
        ctx.book.missing("collide.moving.n", "moving_boxes rows")
        return
    quotes.size(ctx.book, "collide.moving.n", ctx.rows.find(n=n, **MOVING))
    body = []
    for structure, rows in sorted(ctx.rows.by("structure", n=n, **MOVING).items(),
                                  key=lambda item: -max(r.value for r in item[1])):
        key = f"collide.moving.{key_part(structure)}"
        quotes.plain(ctx.book, key + ".rate", [rows], unit="steps/s")
        changed = ctx.rows.find(n=n, structure=structure, **dict(MOVING, metric="pairs_changed_per_step"))
        quotes.count(ctx.book, key + ".changed", [changed])
        body.append([name(structure), ref(key + ".rate"), ref(key + ".changed")])
    ctx.table("collide_moving.tex", tabular("lrr", ["structure", "steps per second",
                                                    "pairs changed per step"], body))


def generate(ctx):
    if ctx.suite_measured(SUITE, bool(ctx.rows.find(suite=SUITE))):
        static(ctx)
        moving(ctx)
