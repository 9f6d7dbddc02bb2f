"""paper/generate.py's command line: read the tables, run every section's generator, write
generated/values.tex, provenance.json, flags.tex and the tables."""

import argparse
import os

from . import book as book_module
from . import tables as tables_module
from .context import Context, read_registry
from .select import Rows
from .sections import (bounding_volumes, collisions, hard_cases, knn, rays, runs, scenes,
                       structures, validity)

SECTIONS = (structures, knn, bounding_volumes, rays, collisions, scenes, hard_cases, validity)


def write_flags(ctx):
    """\\sbmeasured{suite} for every suite with rows: the text's \\sbif{suite}{...}{...}."""
    lines = [f"\\sbmeasured{{{suite}}}" for suite in sorted(ctx.measured)]
    ctx.table("flags.tex", "\n".join(lines) + "\n")


def generate(results_dir, out_dir, figure_runs=None):
    """figure_runs: the plotting run's manifest ({figure: [run ids]}); by default
    <out_dir>/figures/runs.json, where scripts/paper.sh draws the figures first."""
    os.makedirs(out_dir, exist_ok=True)
    tables = tables_module.read_tables(results_dir) if os.path.isdir(results_dir) else []
    registry = read_registry(results_dir)
    ctx = Context(rows=Rows(tables, registry), book=book_module.Book(), out_dir=out_dir,
                  registry=registry, tables=tables)
    for section in SECTIONS:
        section.generate(ctx)
    runs.generate(ctx, results_dir,
                  figure_runs or os.path.join(out_dir, "figures", "runs.json"))
    ctx.book.write(out_dir)
    write_flags(ctx)
    return ctx


def main(argv=None):
    paper = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--results", default=os.path.join(os.path.dirname(paper), "results"))
    parser.add_argument("--out", default=os.path.join(paper, "generated"))
    parser.add_argument("--figure-runs", default=None,
                        help="the figures' run manifest (plot_results.py --runs-manifest); "
                             "default: OUT/figures/runs.json if it exists")
    args = parser.parse_args(argv)
    ctx = generate(args.results, args.out, args.figure_runs)
    missing = sum(1 for e in ctx.book.entries.values() if e["operation"] == "not_measured")
    print(f"generate: {len(ctx.book.entries)} values ({missing} not measured in this run), "
          f"suites measured: {', '.join(sorted(ctx.measured)) or 'none'} -> {args.out}")
    return 0
