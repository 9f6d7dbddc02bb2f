"""The captions' run lists: runs.figure.<figure> from the plotting run's manifest (what
plots/plot_results.py --runs-manifest writes), and every \\sbruns in the text names the figure
it captions."""

import json
import os
import re
import tempfile
import unittest

from tests import support
from sbpaper import cli
from sbpaper.latex import key_part
from sbpaper.sections import runs

FIGURE = re.compile(r"\\sbfigure\{([^{}]*)\}")
RUNS = re.compile(r"\\sbruns\{([^{}]*)\}\{([^{}]*)\}")
COMMENT = re.compile(r"(?<!\\)%.*$", re.MULTILINE)


class RunListTest(unittest.TestCase):
    def test_a_few_runs_are_listed_in_time_order(self):
        text = runs.run_list(["raycast-full-20261126T132408Z-f2edf77",
                              "raycast-quick-20261126T125510Z-c88205a"])
        self.assertEqual(text, r"\texttt{raycast-quick-20261126T125510Z-c88205a}, "
                               r"\texttt{raycast-full-20261126T132408Z-f2edf77}")

    def test_many_runs_give_the_count_and_first_and_last(self):
        ids = [f"raycast-full-20261126T13{m:02d}00Z-f2edf77" for m in range(7)]
        text = runs.run_list(reversed(ids))
        self.assertTrue(text.startswith("7 runs, from "), text)
        self.assertIn(ids[0], text)
        self.assertIn(ids[-1], text)
        self.assertNotIn(ids[3], text)


class FigureRunsTest(unittest.TestCase):
    def test_manifest_defines_a_key_per_figure(self):
        with tempfile.TemporaryDirectory() as out:
            manifest = os.path.join(out, "runs.json")
            with open(manifest, "w") as handle:
                json.dump({"knn_summary": ["knn-quick-20261126T120727Z-c88205a"]}, handle)
            cli.generate(support.results_dir(), out, figure_runs=manifest)
            with open(os.path.join(out, "provenance.json")) as handle:
                entry = json.load(handle)["runs.figure.knn-summary"]
        self.assertEqual(entry["runs"], ["knn-quick-20261126T120727Z-c88205a"])
        self.assertEqual(entry["text"], r"\texttt{knn-quick-20261126T120727Z-c88205a}")

    def test_every_sbruns_names_the_figure_it_captions(self):
        for path in support.hand_written_tex():
            with open(path, encoding="utf-8") as handle:
                text = COMMENT.sub("", handle.read())
            for block in re.split(r"(?=\\sbfigure\{)", text)[1:]:
                figure = FIGURE.match(block).group(1)
                found = RUNS.search(block)
                self.assertIsNotNone(found, f"{os.path.basename(path)}: {figure} names no runs")
                self.assertEqual(found.group(1), key_part(figure), os.path.basename(path))

    def test_the_paper_draws_the_summary_family(self):
        with open(os.path.join(support.REPO, "scripts", "paper.sh"), encoding="utf-8") as handle:
            families = re.search(r"^families=(\S+)", handle.read(), re.MULTILINE).group(1)
        self.assertIn("summary", families.split(","))
        used = set()
        for path in support.hand_written_tex():
            with open(path, encoding="utf-8") as handle:
                used |= set(FIGURE.findall(handle.read()))
        self.assertTrue({f for f in used if f.endswith("_summary")}, "no summary figure")


if __name__ == "__main__":
    unittest.main()
