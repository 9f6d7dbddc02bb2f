"""kNN and range queries (knn.csv): the reference case (uniform, 3D double, largest n), the
ratios across workloads, approximate kNN (recall against time), growth exponents, real data and
the dynamic workloads."""

from .. import quotes
from ..latex import key_part, name, ref, tabular

SUITE = "knn"
REF = dict(workload="uniform", dim="3", scalar="double")
QUERIES = (("knn", "k=1", "kNN, $k=1$", "knn-k1"), ("knn", "k=10", "kNN, $k=10$", "knn-k10"),
           ("radius", None, "radius", "radius"))
ORACLE = "brute_force"


def _query_rows(ctx, operation, params, structure, n, metric="time_per_op", **where):
    where = dict(REF, **where)
    rows = ctx.rows.find(suite=SUITE, operation=operation, metric=metric, structure=structure,
                         n=n, **where)
    return [r for r in rows if params is None or r["params"] == params]


def reference(ctx, n):
    """The table of the reference case and, per query, kd_tree over the fastest peer."""
    structures = [s for s in ctx.rows.values_of("structure", suite=SUITE, operation="knn",
                                                metric="time_per_op", n=n, **REF) if s != ORACLE]
    figures = [(op, params, label, tag, "time_per_op") for op, params, label, tag in QUERIES]
    figures += [("build", None, "build", "build", "build_time"),
                ("build", None, "memory per point", "bytes", "bytes_per_point")]
    body = []
    for operation, params, label, tag, metric in figures:
        cells = [label]
        for structure in structures:
            key = f"knn.ref.{tag}.{key_part(structure)}"
            rows = _query_rows(ctx, operation, params, structure, n, metric)
            if metric == "bytes_per_point":
                quotes.plain(ctx.book, key, [rows], unit="B")
            else:
                quotes.time(ctx.book, key, rows)
            cells.append(ref(key))
        body.append(cells)
        _ratio_to_fastest_peer(ctx, tag, operation, params, metric, structures, n)
    ctx.table("knn_reference.tex", tabular("l" + "r" * len(structures),
                                           ["figure"] + [name(s) for s in structures], body))


def _ratio_to_fastest_peer(ctx, tag, operation, params, metric, structures, n):
    ours = _query_rows(ctx, operation, params, "kd_tree", n, metric)
    peers = {s: _query_rows(ctx, operation, params, s, n, metric)
             for s in structures if s != "kd_tree"}
    peers = {s: rows for s, rows in peers.items() if rows}
    key = f"knn.ref.{tag}.ratio"
    if not ours or not peers:
        ctx.book.missing(key, f"{tag}: kd_tree and a peer at n={n}")
        ctx.book.missing(key + ".peer", "the fastest peer")
        return
    best = min(peers, key=lambda s: sorted(r.value for r in peers[s])[len(peers[s]) // 2])
    quotes.ratio(ctx.book, key, [ours, peers[best]], "ratio")
    ctx.book.word(key + ".peer", name(best))


def across_workloads(ctx, n):
    """kd_tree / peer time ratios (the harness's time_ratio rows) over the generated workloads."""
    for peer in ("cgal_kd_tree", "nanoflann"):
        for params, tag in (("k=10", "k10"), ("k=1", "k1")):
            groups = {}
            for row in ctx.rows.find(suite=SUITE, operation="knn", metric="time_ratio",
                                     structure=peer, params=params, n=n, dim="3",
                                     scalar="double"):
                if not row["workload"].startswith("real:"):
                    groups.setdefault(row["workload"], []).append(row)
            base = f"knn.wl.{tag}.{key_part(peer)}"
            for op in ("min", "max"):
                quotes.ratio(ctx.book, f"{base}.{op}", list(groups.values()), op)
            quotes.count(ctx.book, f"{base}.workloads", list(groups.values()), "count")
            worst = max(groups, key=lambda w: groups[w][0].value) if groups else None
            if worst:
                ctx.book.word(f"{base}.worst", name(worst))
            else:
                ctx.book.missing(f"{base}.worst", "workloads")
            quotes.ratio(ctx.book, f"{base}.lattice", [groups.get("lattice", [])])


def _configuration(row):
    """The winning peer and its settings, from a best_peer_ratio row's params (the operation's
    own params come first and are dropped)."""
    settings = [item for item in row["params"].split(";") if item and not item.startswith(("k=", "eps=", "r="))]
    return name(row["structure"]) + (" (" + ", ".join(name(s) for s in settings) + ")" if settings else "")


def best_peer(ctx, n):
    """kd_tree over the fastest configuration of any peer in the same run (the tuning sweep's
    best_peer_ratio rows), per workload at the reference size and per real point set."""
    body = []
    workloads = ctx.rows.values_of("workload", suite=SUITE, metric="best_peer_ratio", dim="3", scalar="double")
    for workload in workloads:
        where = dict(suite=SUITE, metric="best_peer_ratio", workload=workload, dim="3", scalar="double")
        sizes = ctx.rows.values_of("n", **where)
        at = n if n in sizes else (max(sizes) if workload.startswith("real:") and sizes else None)
        if at is None:
            continue
        cells = [name(workload)]
        for params, tag in (("k=1", "k1"), ("k=10", "k10")):
            rows = [r for r in ctx.rows.find(n=at, operation="knn", **where)
                    if r["params"] == params or r["params"].startswith(params + ";")]
            key = f"knn.best.{key_part(workload)}.{tag}"
            quotes.ratio(ctx.book, key, [rows])
            cells += [ref(key), _configuration(rows[0]) if rows else "---"]
        body.append(cells)
    if not body:
        ctx.book.missing("knn.best.table", "best_peer_ratio rows (a run with the tuning sweep)")
        return
    ctx.table("knn_best_peer.tex", tabular("lrlrl", ["workload", "$k=1$", "fastest peer", "$k=10$", "fastest peer"],
                                           body))


def query_order(ctx, n):
    """Batched kNN (k=10) as given and in Morton order (knn_batch rows): kd_tree's time, its ratio to
    the fastest peer given the same order, and its speedup on every core, per workload."""
    body = []
    workloads = ctx.rows.values_of("workload", suite=SUITE, operation="knn_batch", metric="time_per_op",
                                   structure="kd_tree", dim="3", scalar="double")
    for workload in workloads:
        where = dict(suite=SUITE, operation="knn_batch", workload=workload, dim="3", scalar="double")
        sizes = ctx.rows.values_of("n", metric="time_per_op", structure="kd_tree", **where)
        at = n if n in sizes else (max(sizes) if workload.startswith("real:") and sizes else None)
        if at is None:
            continue
        cells = [name(workload)]
        for order in ("as_given", "morton"):
            params = f"k=10;order={order}"
            base = f"knn.order.{key_part(workload)}.{key_part(order)}"
            quotes.time(ctx.book, base + ".time", [r for r in ctx.rows.find(n=at, metric="time_per_op", structure="kd_tree", **where)
                                                   if r["params"] == params])
            best = [r for r in ctx.rows.find(n=at, metric="best_peer_ratio", **where)
                    if r["params"] == params or r["params"].startswith(params + ";")]
            quotes.ratio(ctx.book, base + ".best", [best])
            cells += [ref(base + ".time"), ref(base + ".best")]
        speedup = [r for r in ctx.rows.find(n=at, metric="speedup", structure="kd_tree", **where)
                   if r["params"].startswith("k=10;order=morton;threads=")]
        key = f"knn.order.{key_part(workload)}.speedup"
        quotes.ratio(ctx.book, key, [speedup])
        cells.append(ref(key))
        # The kd-tree's bulk build on every core over one thread (parallel_build rows, measured
        # beside the batches).
        build = [r for r in ctx.rows.find(suite=SUITE, operation="parallel_build", workload=workload, dim="3",
                                          scalar="double", n=at, metric="speedup", structure="kd_tree")
                 if r["params"].startswith("threads=")]
        key = f"knn.order.{key_part(workload)}.build-speedup"
        if build:
            quotes.ratio(ctx.book, key, [build])
            cells.append(ref(key))
        else:
            cells.append("---")
        body.append(cells)
    # The text quotes the far-query workload's ratios: defined (as not measured) even when a
    # run has no clusters_far rows, as the smoke preset's has not.
    for order in ("as_given", "morton"):
        key = f"knn.order.clusters-far.{key_part(order)}.best"
        if key not in ctx.book.entries:
            ctx.book.missing(key, "knn_batch best_peer_ratio rows of workload clusters_far")
    if not body:
        ctx.book.missing("knn.order.table", "knn_batch rows (a run with the batched measurement)")
        return
    ctx.table("knn_query_order.tex", tabular("lrrrrrr", ["workload", "as given", "/ best peer", "Morton order",
                                                          "/ best peer", "Morton, all cores", "build, all cores"], body))


def real_data(ctx):
    groups = {}
    for row in ctx.rows.find(suite=SUITE, operation="knn", metric="time_ratio",
                             structure="cgal_kd_tree", params="k=10"):
        if row["workload"].startswith("real:"):
            groups.setdefault(row["workload"], []).append(row)
    quotes.count(ctx.book, "knn.real.sets", list(groups.values()), "count")
    for op in ("min", "max"):
        quotes.ratio(ctx.book, f"knn.real.k10.cgal-kd-tree.{op}", list(groups.values()), op)


def recall(ctx, n):
    """Recall and time per eps at the reference n: the table behind the recall-vs-time front."""
    structures = [s for s in ctx.rows.values_of("structure", suite=SUITE, operation="approx_knn",
                                                metric="recall", n=n, **REF)]
    params = ctx.rows.values_of("params", suite=SUITE, operation="approx_knn", metric="recall",
                                n=n, **REF)
    body = []
    for p in params:
        eps = p.split("eps=")[-1]
        cells = [f"$\\varepsilon={eps}$" if eps.replace(".", "").isdigit() else p]
        for s in structures:
            base = f"knn.recall.{key_part(p)}.{key_part(s)}"
            quotes.plain(ctx.book, base + ".recall",
                         [_query_rows(ctx, "approx_knn", p, s, n, "recall")], digits=2)
            quotes.time(ctx.book, base + ".time", _query_rows(ctx, "approx_knn", p, s, n))
            cells.append(f"{ref(base + '.recall')} / {ref(base + '.time')}")
        body.append(cells)
    ctx.table("knn_recall.tex", tabular("l" + "r" * len(structures),
                                        ["$\\varepsilon$"] + [name(s) for s in structures], body))
    exact = "knn.recall.exact.kd-tree.time"
    quotes.time(ctx.book, exact, _query_rows(ctx, "knn", "k=10", "kd_tree", n))


def exponents(ctx):
    for structure in ("kd_tree", "nanoflann", "cgal_kd_tree"):
        for operation, params, metric, tag in (("knn", "k=10", "time_per_op", "knn-k10"),
                                               ("build", "", "build_time", "build")):
            groups = ctx.rows.by("n", suite=SUITE, structure=structure, operation=operation,
                                 params=params, metric=metric, **REF)
            key = f"knn.exp.{tag}.{key_part(structure)}"
            if len(groups) < 2:
                ctx.book.missing(key, "two sizes n")
                continue
            quotes.plain(ctx.book, key, [groups[n] for n in sorted(groups)], "exponent", digits=2)


def dynamic(ctx):
    """Speed-up ratios of the dynamic workloads at their largest n (kd_tree's rows)."""
    for operation, params, tag in (("insert_hinted", "stream=walks;m=n/2", "hint-walks"),
                                   ("insert_hinted", "stream=morton;m=n/2", "hint-morton"),
                                   ("insert_bulk", "into=empty;m=n", "bulk-empty"),
                                   ("insert_bulk", "into=n;m=n/10", "bulk-merge"),
                                   ("erase_bulk", "range=50%", "erase-half")):
        where = dict(suite=SUITE, structure="kd_tree", operation=operation, params=params,
                     metric="speedup_ratio", workload="uniform")
        n = ctx.rows.largest_n(**where)
        quotes.ratio(ctx.book, f"knn.dyn.{tag}", [ctx.rows.find(n=n, **where) if n else []])
    where = dict(suite=SUITE, operation="churn", metric="time_per_op", workload="uniform")
    n = ctx.rows.largest_n(structure="kd_tree", **where)
    for structure in ("kd_tree", "nanoflann_dynamic"):
        rows = ctx.rows.find(structure=structure, n=n, **where) if n else []
        quotes.time(ctx.book, f"knn.dyn.churn.{key_part(structure)}", rows)


def reference_size(ctx):
    """The largest n at which the most generated workloads were measured (3D double kNN, uniform
    among them): a table at a larger size covering fewer workloads (knn_1e7.csv: uniform only)
    feeds the growth exponents, not the comparisons across workloads."""
    workloads_at = {}
    for row in ctx.rows.find(suite=SUITE, operation="knn", metric="time_per_op", dim="3", scalar="double"):
        if not row["workload"].startswith("real:"):
            workloads_at.setdefault(row.n, set()).add(row["workload"])
    sizes = [n for n, workloads in workloads_at.items() if REF["workload"] in workloads]
    return max(sizes, key=lambda n: (len(workloads_at[n]), n)) if sizes else None


def generate(ctx):
    n = reference_size(ctx)
    if not ctx.suite_measured(SUITE, n is not None):
        return
    quotes.size(ctx.book, "knn.n", _query_rows(ctx, "knn", "k=10", "kd_tree", n))
    reference(ctx, n)
    across_workloads(ctx, n)
    best_peer(ctx, n)
    query_order(ctx, n)
    real_data(ctx)
    recall(ctx, n)
    exponents(ctx)
    dynamic(ctx)
