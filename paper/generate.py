#!/usr/bin/python3
"""Write paper/generated/ from the result tables: every number the paper quotes, with its
provenance.  Usage: /usr/bin/python3 paper/generate.py [--results DIR] [--out DIR]"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from sbpaper.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
