"""Ray casting (raycast*.csv): every structure and peer at the largest n of each generated mesh,
incoherent and coherent rays, and the bvh against Embree and CGAL's AABB_tree.  Head-to-head
reruns of one figure (several runs, one run_id each) are pooled by their median."""

from .. import quotes
from ..latex import key_part, name, ref, tabular

SUITE = "raycast"
KINDS = (("rays=incoherent", "incoherent"), ("rays=coherent", "coherent"))
PEERS = ("embree", "embree_robust", "cgal_aabb_tree")


def _ray_rows(ctx, workload, n, kind, structure, bv=None):
    rows = ctx.rows.find(suite=SUITE, operation="ray", metric="time_per_op", workload=workload,
                         n=n, structure=structure)
    rows = [r for r in rows if r["params"].split(";camera=")[0] == kind]
    return [r for r in rows if bv is None or r["bv"] == bv]


def head_to_head(ctx, workload):
    where = dict(suite=SUITE, operation="ray", metric="time_per_op", workload=workload)
    n = ctx.rows.largest_n(structure="embree", **where)
    key = f"rays.{workload}"
    if n is None:
        ctx.book.missing(key + ".n", f"embree on {workload}")
        return []
    quotes.size(ctx.book, key + ".n", ctx.rows.find(n=n, structure="embree", **where))
    structures = ("bvh",) + PEERS
    body = []
    for kind, tag in KINDS:
        cells = [f"{name(workload)}, {tag}"]
        for structure in structures:
            rows = _ray_rows(ctx, workload, n, kind, structure,
                             "aabb" if structure == "bvh" else None)
            quotes.time(ctx.book, f"{key}.{tag}.{key_part(structure)}", rows)
            cells.append(ref(f"{key}.{tag}.{key_part(structure)}"))
        ours = _ray_rows(ctx, workload, n, kind, "bvh", "aabb")
        for peer in ("embree", "cgal_aabb_tree"):
            quotes.ratio(ctx.book, f"{key}.{tag}.bvh-over-{key_part(peer)}",
                         [ours, _ray_rows(ctx, workload, n, kind, peer)], "ratio")
        cells.append(ref(f"{key}.{tag}.bvh-over-embree"))
        body.append(cells)
    one_row_per_run = {r["run_id"]: r for r in ctx.rows.find(n=n, structure="embree", **where)}
    quotes.count(ctx.book, key + ".runs", [[r] for r in one_row_per_run.values()], "count")
    return body


def generate(ctx):
    if not ctx.suite_measured(SUITE, bool(ctx.rows.find(suite=SUITE))):
        return
    body = head_to_head(ctx, "sphere") + head_to_head(ctx, "soup")
    structures = ("bvh",) + PEERS
    ctx.table("rays_peers.tex", tabular("l" + "r" * (len(structures) + 1),
                                        ["mesh, rays"] + [name(s) for s in structures] +
                                        ["bvh / embree"], body))
