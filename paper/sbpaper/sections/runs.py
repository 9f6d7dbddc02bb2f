"""The runs behind the tables (results/runs/<run_id>.json): the machine, compiler, flags,
commit, seeds and wall time of each run a quoted row comes from — the reproducibility
appendix's table and the methodology's machine facts."""

import json
import os

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
                       ("threads_used", "threads-used"), ("host", "host")):
        values = sorted({str(s.get(field, "")).strip() for s in present if s.get(field) is not None})
        text = "; ".join(escape(v) for v in values) if values else "not recorded"
        ctx.book.word(f"machine.{key}", r"\texttt{" + text + "}" if key == "flags" else text)
    commits = {s.get("commit", "") for s in present}
    ctx.book.word("runs.count", str(len(sidecars)))
    ctx.book.word("runs.commits", str(len(commits)))
    ctx.book.word("runs.dirty", str(sum(1 for c in commits if c.endswith("-dirty"))))
    ctx.book.word("runs.missing-sidecars", str(sum(1 for s in sidecars.values() if s is None)))


def suite_runs(ctx):
    """runs.suite.<suite>: the run ids a suite's figures and tables are drawn from (captions)."""
    suites = {entry.get("name") for entry in ctx.registry.get("suites", [])}
    suites |= {row["suite"] for row in ctx.rows.usable}
    for suite in sorted(s for s in suites if s):
        ids = sorted({row["run_id"] for row in ctx.rows.usable if row["suite"] == suite})
        text = ", ".join(r"\texttt{" + escape(i) + "}" for i in ids) or "none in this run"
        ctx.book.word(f"runs.suite.{key_part(suite)}", text)


def generate(ctx, results_dir):
    run_ids = {row["run_id"] for row in ctx.rows.usable}
    sidecars = read_sidecars(results_dir, run_ids)
    machine(ctx, sidecars)
    run_table(ctx, sidecars)
    suite_runs(ctx)
