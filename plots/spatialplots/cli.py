"""The command line of plots/plot_results.py: read the registry and the tables, then discover
the figure families and run each of them."""

import argparse
import json
import os

from . import family as families_module
from . import figures, formats
from .core import label_of, series_label
from .io import REGISTRY_FILE, RegistryError, note, read_registry, read_results, table_names
from .style import StyleBook

DESCRIPTION = "Plot spatialbench results: read results/*.csv, write PNGs."


def main(argv=None, repo=None, families_package="spatialplots.families"):
    """Exit code: 0 (also when there is nothing to plot), 1 when results/registry.json is
    missing or malformed."""
    repo = repo or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument("--results", default=os.path.join(repo, "results"),
                        help="directory of *.csv tables and registry.json (default: %(default)s)")
    parser.add_argument("--out", default=os.path.join(repo, "plots"),
                        help="directory for the PNGs (default: %(default)s)")
    parser.add_argument("--include-unvalidated", action="store_true",
                        help="draw timing rows with validated=false hollow/dashed "
                             "instead of skipping them")
    parser.add_argument("--formats", default="png",
                        help="comma-separated file formats of every figure: png, pdf "
                             "(vector, for print) or both (default: %(default)s)")
    parser.add_argument("--families", default="",
                        help="comma-separated figure families to draw (default: all)")
    parser.add_argument("--runs-manifest", default="",
                        help="also write this JSON file: {figure name: [run ids of its rows]} "
                             "(the paper's captions read it)")
    args = parser.parse_args(argv)
    try:
        formats.choose([f.strip() for f in args.formats.split(",") if f.strip()])
    except ValueError as error:
        parser.error(str(error))

    figures.forget_runs()
    names = table_names(args.results)
    if names is None:
        return 0
    try:
        registry = read_registry(os.path.join(args.results, REGISTRY_FILE))
    except RegistryError as error:
        note(f"error: {error}")
        return 1
    rows = read_results(args.results, registry, names)
    if not rows:
        note("no rows to plot")
        return 0

    os.makedirs(args.out, exist_ok=True)
    styles = StyleBook(registry, {label_of(r) for r in rows} | {series_label(r, registry) for r in rows})
    families = families_module.discover(families_package)
    wanted = {f.strip() for f in args.families.split(",") if f.strip()}
    drawn = [f for f in families if not wanted or f.name in wanted]
    written = []
    for family in drawn:
        family_rows = families_module.rows_for(family, rows, families)
        if family.suites is not None and not family_rows:
            continue
        figures.family_rows(row for row in family_rows
                            if row.validated or args.include_unvalidated)
        context = families_module.Context(rows=family_rows, registry=registry, styles=styles,
                                          out_dir=args.out,
                                          include_unvalidated=args.include_unvalidated)
        written += family.draw(context) or []
    if args.runs_manifest:
        write_manifest(args.runs_manifest, figures.figure_runs())
    note(f"{len(written)} figure(s) written to {args.out} as {', '.join(formats.chosen())}")
    return 0


def write_manifest(path, runs):
    """{figure name: [run ids]} as JSON, written to a temporary file renamed into place."""
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    temp = path + ".tmp"
    with open(temp, "w", encoding="utf-8") as handle:
        json.dump(runs, handle, indent=1, sort_keys=True)
        handle.write("\n")
    os.replace(temp, path)
