"""The runs behind the tables (results/runs/<run_id>.json): the machine, compiler, flags,
commit, seeds and wall time of each run a quoted row comes from — the reproducibility
appendix's table and the methodology's machine facts; and the run ids the captions name:
runs.suite.<suite> (every usable row of the suite) and runs.figure.<figure> (the rows the
figure drew, from the plotting run's manifest, plots/plot_results.py --runs-manifest)."""

import json
import os
import re

from ..book import tally
from ..latex import escape, key_part, ref, tabular


def read_sidecars(results_dir, run_ids):
    found = {}
    for run_id in sorted(run_ids):
        path = os.path.join(results_dir, "runs", run_id + ".json")
        try:
            with open(path, encoding="utf-8") as handle:
                found[run_id] = json.load(handle)
        except (OSError, ValueError):
            found[run_id] = None
    return found


def _seeds(sidecar):
    seeds = sidecar.get("seeds") or {}
    return ", ".join(f"{k}={v}" for k, v in sorted(seeds.items())) or "none"


def run_table(ctx, sidecars):
    body = []
    for i, (run_id, sidecar) in enumerate(sorted(sidecars.items())):
        key = f"run.{key_part(run_id)}"
        ctx.book.word(key + ".id", r"\texttt{" + escape(run_id) + "}")
        if sidecar is None:
            body.append([ref(key + ".id"), r"\multicolumn{4}{l}{no sidecar}"])
            continue
        ctx.book.word(key + ".commit", r"\texttt{" + escape(sidecar.get("commit", "?")[:12] +
                                                          ("+" if "dirty" in sidecar.get("commit", "") else "")) + "}")
        ctx.book.word(key + ".seeds", escape(_seeds(sidecar)))
        tally(ctx.book, key + ".rows", ctx.tables, "usable", run_id)
        ctx.book.word(key + ".wall", f"{float(sidecar.get('wall_seconds', 0)):.0f}\\,s")
        body.append([ref(key + x) for x in (".id", ".commit", ".seeds", ".rows", ".wall")])
    ctx.table("runs.tex", tabular("llllr", ["run", "commit", "seeds", "usable rows", "wall"], body))


def machine(ctx, sidecars):
    """The machine facts: taken from the sidecars, and the same in all of them or listed."""
    present = [s for s in sidecars.values() if s]
    for field, key in (("cpu", "cpu"), ("compiler", "compiler"), ("cxx_flags", "flags"),
                       ("build_type", "build-type"), ("hardware_threads", "threads"),
                       ("threads_used", "threads-used"), ("parallel_threads", "parallel-threads"),
                       ("host", "host")):
        values = sorted({str(s.get(field, "")).strip() for s in present if s.get(field) is not None})
        text = "; ".join(escape(v) for v in values) if values else "not recorded"
        ctx.book.word(f"machine.{key}", r"\texttt{" + text + "}" if key == "flags" else text)
    commits = {s.get("commit", "") for s in present}
    ctx.book.word("runs.count", str(len(sidecars)))
    ctx.book.word("runs.commits", str(len(commits)))
    ctx.book.word("runs.dirty", str(sum(1 for c in commits if c.endswith("-dirty"))))
    ctx.book.word("runs.missing-sidecars", str(sum(1 for s in sidecars.values() if s is None)))


RUNS_LISTED = 3  # a caption lists this many run ids; more: the count, the first and the last
_STAMP = re.compile(r"\d{8}T\d{6}Z")  # the UTC timestamp inside a run id


def chronological(ids):
    """Distinct run ids, oldest first (by the timestamp in the id, then the id), as the plots'
    footers order them."""
    def when(run_id):
        found = _STAMP.search(run_id)
        return (found.group(0) if found else "", run_id)
    return sorted(set(ids) - {""}, key=when)


def run_list(ids):
    """A caption's run list: up to RUNS_LISTED ids, else the count with the first and last."""
    ids = chronological(ids)
    if not ids:
        return "none in this run"
    names = [r"\texttt{" + escape(i) + "}" for i in ids]
    if len(names) <= RUNS_LISTED:
        return ", ".join(names)
    return f"{len(names)} runs, from {names[0]} to {names[-1]}"


def suite_runs(ctx):
    """runs.suite.<suite>: the run ids a suite's figures and tables are drawn from (captions)."""
    suites = {entry.get("name") for entry in ctx.registry.get("suites", [])}
    suites |= {row["suite"] for row in ctx.rows.usable}
    for suite in sorted(s for s in suites if s):
        ids = chronological(row["run_id"] for row in ctx.rows.usable if row["suite"] == suite)
        ctx.book.runs(f"runs.suite.{key_part(suite)}", run_list(ids), ids)


def read_manifest(path):
    """{figure name: [run ids]} written by plots/plot_results.py --runs-manifest; {} when the
    figures were not drawn (the generator run alone, as by the tests)."""
    try:
        with open(path, encoding="utf-8") as handle:
            data = json.load(handle)
    except (OSError, ValueError):
        return {}
    return {str(k): [str(i) for i in v] for k, v in data.items() if isinstance(v, list)}


def figure_runs(ctx, manifest):
    """runs.figure.<figure>: the runs of the rows each drawn figure comes from; a caption
    writes \\sbruns{<figure>}{<suite>}, which falls back to runs.suite.<suite> for a figure
    the manifest lacks."""
    for figure, ids in sorted(manifest.items()):
        ids = chronological(ids)
        ctx.book.runs(f"runs.figure.{key_part(figure)}", run_list(ids), ids)


def generate(ctx, results_dir, manifest_path=None):
    run_ids = {row["run_id"] for row in ctx.rows.usable}
    sidecars = read_sidecars(results_dir, run_ids)
    machine(ctx, sidecars)
    run_table(ctx, sidecars)
    suite_runs(ctx)
    figure_runs(ctx, read_manifest(manifest_path) if manifest_path else {})
