#!/usr/bin/python3
"""Plot spatialbench results: read results/*.csv and results/registry.json, write PNGs.

Run with Debian's interpreter (it sees python3-matplotlib and python3-numpy):

    /usr/bin/python3 plots/plot_results.py [--results DIR] [--out DIR] [--include-unvalidated]

This is only the entry point: the figures are drawn by the figure families of the package
plots/spatialplots/ (one module per family under spatialplots/families/, found by discovery).
See plots/README.md for what each PNG shows.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from spatialplots.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
