"""Bounding volumes (bv.csv): tightness against fit time and overlap-test time per type and
fitting method (geometric means over the shapes, as bv_tradeoff.png draws them), ours against
CGAL's fits per shape, and what a volume type buys inside a BVH (raycast.csv, collide.csv)."""

from collections import defaultdict

from .. import quotes
from ..latex import key_part, name, ref, tabular

SUITE = "bv"
REFERENCE_N = 100000  # the n the fits are compared at (else the largest n), as in the plot
CGAL_TARGETS = (("sphere", "minimum", "min_sphere_of_spheres_d", "ball"),
                ("convex_hull", "quickhull", "convex_hull_3", "hull"))


def _method(row):
    return dict(p.split("=", 1) for p in row["params"].split(";") if "=" in p).get("method", "")


def _per_workload(rows, n_choice):
    """{workload: rows at the chosen n}."""
    by_workload = defaultdict(lambda: defaultdict(list))
    for row in rows:
        by_workload[row["workload"]][row.n].append(row)
    return {w: per_n[n_choice(sorted(per_n))] for w, per_n in by_workload.items()}


def fits(ctx):
    at_ref = lambda ns: REFERENCE_N if REFERENCE_N in ns else max(ns)  # noqa: E731
    series = defaultdict(list)
    for row in ctx.rows.find(suite=SUITE, operation="fit"):
        series[(row["structure"], row["bv"], _method(row))].append(row)
    body = []
    for (structure, bv, method), rows in sorted(series.items()):
        tight = _per_workload([r for r in rows if r["metric"] == "tightness"], at_ref)
        times = _per_workload([r for r in rows if r["metric"] == "fit_time"], at_ref)
        if not tight or not times:
            continue
        base = f"bv.fit.{key_part(structure)}.{key_part(bv)}.{key_part(method)}"
        quotes.plain(ctx.book, base + ".tightness", list(tight.values()), "geomean")
        quotes.times(ctx.book, base + ".time", list(times.values()), "geomean")
        body.append([name(bv), name(method) + ("" if structure == "spatialbench" else " (CGAL)"),
                     ref(base + ".tightness"), ref(base + ".time")])
    ctx.table("bv_fits.tex", tabular("llrr", ["type", "fit", "tightness", "fit time"], body))


def overlaps(ctx):
    series = defaultdict(list)
    for row in ctx.rows.find(suite=SUITE, operation="overlap"):
        test = dict(p.split("=", 1) for p in row["params"].split(";")).get("test", "")
        series[(row["bv"], _method(row), test)].append(row)
    body = []
    for (bv, method, test), rows in sorted(series.items()):
        largest = lambda ns: max(ns)  # noqa: E731
        times = _per_workload([r for r in rows if r["metric"] == "time_per_op"], largest)
        fp = _per_workload([r for r in rows if r["metric"] == "false_positive_rate_shapes"],
                           largest)
        if not times or not fp:
            continue
        base = f"bv.overlap.{key_part(bv)}.{key_part(method)}.{key_part(test)}"
        quotes.times(ctx.book, base + ".time", list(times.values()), "geomean")
        quotes.plain(ctx.book, base + ".fp", list(fp.values()), "mean", digits=2)
        body.append([name(bv), name(method), name(test), ref(base + ".time"), ref(base + ".fp")])
    ctx.table("bv_overlaps.tex", tabular("lllrr", ["type", "fit", "test", "time",
                                                   "false positives"], body))


def against_cgal(ctx):
    """Ours over CGAL's fit time per shape, at the largest n, for the exact ball and hull."""
    workloads = ctx.rows.values_of("workload", suite=SUITE, operation="fit", metric="fit_time",
                                   structure="cgal")
    body = []
    for workload in workloads:
        cells = [name(workload)]
        for bv, ours, theirs, tag in CGAL_TARGETS:
            where = dict(suite=SUITE, operation="fit", metric="fit_time", workload=workload, bv=bv)
            mine = [r for r in ctx.rows.find(structure="spatialbench", **where)]
            other = [r for r in ctx.rows.find(structure="cgal", **where) if _method(r) == theirs]
            n = max({r.n for r in mine} & {r.n for r in other}, default=None)
            key = f"bv.cgal.{tag}.{key_part(workload)}"
            pick = lambda rows: [r for r in rows if r.n == n]  # noqa: E731
            mine = [r for r in pick(mine) if _method(r) == ours]
            quotes.ratio(ctx.book, key, [mine, pick(other)], "ratio")
            cells.append(ref(key))
        body.append(cells)
    ctx.table("bv_cgal.tex", tabular("lrr", ["shape", "min.\\ ball: ours/CGAL",
                                             "hull: ours/CGAL"], body))


def in_a_bvh(ctx):
    """Per volume type inside a BVH: time per incoherent ray on the sphere mesh and candidate
    pairs / false-positive ratio of the triangle soup's self-intersection, each at its largest n."""
    ray = dict(suite="raycast", operation="ray", params="rays=incoherent", metric="time_per_op",
               workload="sphere")
    pairs = dict(suite="collide", workload="triangles", operation="candidate_pairs")
    volumes_at = ctx.rows.by("n", **ray)  # the n where the most volume types were measured
    n_ray = max(volumes_at, key=lambda n: (len({r["bv"] for r in volumes_at[n]}), n),
                default=None)
    n_pairs = ctx.rows.largest_n(metric="pairs", **pairs)
    volumes = sorted({r["bv"] for r in ctx.rows.find(**ray) if r["structure"].startswith("bvh")}
                     | {r["bv"] for r in ctx.rows.find(metric="pairs", **pairs)} - {"", "-"})
    body = []
    for bv in volumes:
        base = f"bvh.bv.{key_part(bv)}"
        rays = [r for r in ctx.rows.find(n=n_ray or 0, bv=bv, **ray)
                if r["structure"] in ("bvh", f"bvh_{bv}")]
        quotes.time(ctx.book, base + ".ray", rays)
        quotes.count(ctx.book, base + ".candidates",
                     [ctx.rows.find(n=n_pairs or 0, bv=bv, metric="pairs", **pairs)])
        quotes.plain(ctx.book, base + ".fp", [ctx.rows.find(n=n_pairs or 0, bv=bv,
                     metric="false_positive_ratio", **pairs)], digits=2)
        body.append([name(bv)] + [ref(base + s) for s in (".ray", ".candidates", ".fp")])
    if n_ray:
        quotes.size(ctx.book, "bvh.bv.n-ray", ctx.rows.find(n=n_ray, **ray))
    else:
        ctx.book.missing("bvh.bv.n-ray", "raycast sphere rows")
    if n_pairs:
        quotes.size(ctx.book, "bvh.bv.n-pairs", ctx.rows.find(n=n_pairs, metric="pairs", **pairs))
    else:
        ctx.book.missing("bvh.bv.n-pairs", "collide triangles rows")
    ctx.table("bvh_volumes.tex", tabular("lrrr", ["type", "time per ray", "candidate pairs",
                                                  "false-positive ratio"], body))


def generate(ctx):
    if ctx.suite_measured(SUITE, bool(ctx.rows.find(suite=SUITE))):
        fits(ctx)
        overlaps(ctx)
        against_cgal(ctx)
    in_a_bvh(ctx)
