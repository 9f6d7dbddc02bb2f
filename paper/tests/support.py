"""Shared by the paper tests: the paper folder, the hand-written .tex files, and one generator
run (into a temporary folder) over the results the tests are pointed at — the committed
results/ by default, or PAPER_RESULTS (CI points it at freshly made smoke tables)."""

import glob
import json
import os
import sys
import tempfile

PAPER = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REPO = os.path.dirname(PAPER)
sys.path.insert(0, PAPER)

from sbpaper import cli  # noqa: E402

_generated = {}


def results_dir():
    return os.environ.get("PAPER_RESULTS", os.path.join(REPO, "results"))


def hand_written_tex():
    """Every .tex under paper/ that a person writes (not generated/, not the build folder)."""
    found = glob.glob(os.path.join(PAPER, "*.tex")) + glob.glob(os.path.join(PAPER, "sections", "*.tex"))
    return sorted(found)


def generated():
    """(output folder, provenance dict) of one generator run, shared by the tests."""
    if "out" not in _generated:
        out = tempfile.mkdtemp(prefix="paper-generated-")
        cli.generate(results_dir(), out)
        with open(os.path.join(out, "provenance.json"), encoding="utf-8") as handle:
            _generated["out"], _generated["provenance"] = out, json.load(handle)
    return _generated["out"], _generated["provenance"]
