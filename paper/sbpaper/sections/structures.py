"""The structures: the complexity table (from the registry, which the harness writes from its
structure and peer lists) and every structure on the knn suite's static queries
(structures.csv) at the largest n of the reference workload."""

from .. import quotes
from ..latex import escape, key_part, name, ref, tabular

SUITE = "structures"
REF = dict(workload="uniform", dim="3", scalar="double")
COLUMNS = (("build", "build"), ("*", "query"), ("build_and_self_pairs", "build + self pairs"))


def complexity_table(ctx):
    body = []
    for entry in ctx.registry.get("structures", []):
        # "spatialbench" names the bv suite's own fits, not a container.
        if entry.get("kind") not in ("library", "example") or entry["name"] == "spatialbench":
            continue
        complexity = entry.get("complexity", {})
        cells = [name(entry["name"])]
        cells += ["$O(" + escape(complexity.get(op, complexity.get("*", "?")))
                  .replace(" ", r"\,") + ")$" for op, _ in COLUMNS]
        body.append(cells)
    ctx.table("complexity.tex", tabular("l" + "c" * len(COLUMNS),
                                        ["structure"] + [label for _, label in COLUMNS], body))


def comparison(ctx, n):
    structures = ctx.rows.values_of("structure", suite=SUITE, operation="knn", params="k=10",
                                    metric="time_per_op", n=n, **REF)
    body = []
    for s in structures:
        base = f"structures.{key_part(s)}"
        cells = [name(s)]
        for operation, params, metric, tag in (("knn", "k=10", "time_per_op", "knn-k10"),
                                               ("build", "", "build_time", "build"),
                                               ("build", "", "bytes_per_point", "bytes")):
            rows = ctx.rows.find(suite=SUITE, structure=s, operation=operation, params=params,
                                 metric=metric, n=n, **REF)
            if metric == "bytes_per_point":
                quotes.plain(ctx.book, f"{base}.{tag}", [rows], unit="B")
            else:
                quotes.time(ctx.book, f"{base}.{tag}", rows)
            cells.append(ref(f"{base}.{tag}"))
        body.append(cells)
    ctx.table("structures_compare.tex",
              tabular("lrrr", ["structure", "kNN $k=10$", "build", "memory/point"], body))


def generate(ctx):
    complexity_table(ctx)
    n = ctx.rows.largest_n(suite=SUITE, operation="knn", metric="time_per_op", **REF)
    if ctx.suite_measured(SUITE, n is not None):
        quotes.size(ctx.book, "structures.n",
                    ctx.rows.find(suite=SUITE, operation="knn", metric="time_per_op", n=n, **REF))
        comparison(ctx, n)
