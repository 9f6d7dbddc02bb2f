"""Hard cases found in the tables: rays whose answers differ between implementations only
within their precision (the raycast suite's `ambiguous_rays`, excused and counted, never
silent), summed per structure; and the kd_tree's worst workload (the lattice ratios are quoted
by the knn section)."""

from collections import defaultdict

from .. import quotes
from ..latex import key_part, name, ref, tabular


def generate(ctx):
    rows = ctx.rows.find(suite="raycast", operation="ray", metric="ambiguous_rays")
    totals = defaultdict(list)
    for row in rows:
        totals[row["structure"]].append(row)
    rays = defaultdict(list)
    for row in ctx.rows.find(suite="raycast", operation="ray", metric="rays"):
        rays[row["structure"]].append(row)
    body = []
    for structure in sorted(totals):
        base = f"hard.ambiguous.{key_part(structure)}"
        quotes.count(ctx.book, base, [[r] for r in totals[structure]], "sum")
        pair_keys = {(r.file, r["workload"], r.n, r["params"], r["run_id"], r["bv"]) for r in totals[structure]}
        cast = [r for r in rays[structure]
                if (r.file, r["workload"], r.n, r["params"], r["run_id"], r["bv"]) in pair_keys]
        quotes.count(ctx.book, base + ".rays", [[r] for r in cast], "sum")
        body.append([name(structure), ref(base), ref(base + ".rays")])
    ctx.table("hard_ambiguous.tex", tabular("lrr", ["structure", "excused disagreements",
                                                    "rays cast"], body))
    if rows:
        quotes.count(ctx.book, "hard.ambiguous.total", [[r] for r in rows], "sum")
    else:
        ctx.book.missing("hard.ambiguous.total", "raycast ambiguous_rays rows")
