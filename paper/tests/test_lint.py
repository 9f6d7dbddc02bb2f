"""The lint over the hand-written .tex: no digit outside the allowed contexts, and every
\\R{key} the text (or a generated table) writes is generated and resolves to rows that exist
and were validated.

The rule.  After removing, from each hand-written .tex file (paper/*.tex, paper/sections/*.tex):
  1. comments (an unescaped % to the end of the line);
  2. the arguments of the commands in ARGUMENT_COMMANDS (keys, labels, file names, package
     options: identifiers, not quantities);
  3. TeX macro parameters (#1 ... #9) and the argument count of \\newcommand;
  4. lengths: a number followed by a TeX unit or by \\linewidth, \\textwidth, \\textheight,
     \\columnwidth;
  5. the notation of approximate search, (1+\\varepsilon) (NOTATION);
no digit may remain.  A measured value, a problem size, a count, a parameter of a run: all of
them are written \\R{key}, which paper/generate.py defines from the tables."""

import csv
import functools
import os
import re
import unittest

from tests import support

ARGUMENT_COMMANDS = ("R", "label", "ref", "eqref", "autoref", "cite", "input", "include",
                     "includegraphics", "usepackage", "documentclass", "url", "IfFileExists",
                     "sbfigure", "sbtable", "sbif", "sbsuitemissing", "sbruns")
_ARGUMENT = re.compile(r"\\(" + "|".join(ARGUMENT_COMMANDS) + r")\*?(\[[^\]]*\])?\{[^{}]*\}")
_COMMENT = re.compile(r"(?<!\\)%.*$", re.MULTILINE)
_PARAMETER = re.compile(r"#\d|(?<=\\newcommand)(\\\w+|\{\\\w+\})\[\d\]")
_LENGTH = re.compile(r"\d+(\.\d+)?\s*(pt|em|ex|cm|mm|in|bp|\\linewidth|\\textwidth|"
                     r"\\textheight|\\columnwidth)")
NOTATION = re.compile(r"\(1\s*\+\s*\\varepsilon\)")
_KEY = re.compile(r"\\R\{([^{}]*)\}")
# \sbruns{figure}{suite} (preamble.tex): runs.figure.<figure> when the figures were drawn, else
# runs.suite.<suite>, which must then be generated.
_RUNS = re.compile(r"\\sbruns\{([^{}]*)\}\{([^{}]*)\}")


def stray_digits(text):
    """[(line number, line)] of the lines that keep a digit after the allowed contexts go."""
    text = _COMMENT.sub("", text)
    text = _ARGUMENT.sub("", text)
    text = _PARAMETER.sub("", text)
    text = _LENGTH.sub("", text)
    text = NOTATION.sub("", text)
    return [(i, line.strip()) for i, line in enumerate(text.splitlines(), 1)
            if re.search(r"\d", line)]


class LintRuleTest(unittest.TestCase):
    """The rule itself, on made-up text."""

    def test_a_typed_number_is_caught(self):
        self.assertTrue(stray_digits(r"the kd-tree takes 3.95\,\textmu s per query"))
        self.assertTrue(stray_digits(r"at $n = 10^6$ points"))

    def test_allowed_contexts_pass(self):
        text = (r"\R{knn.ref.knn-k10.kd-tree} in Section~\ref{sec:knn2} % 42 in a comment" "\n"
                r"\usepackage[margin=2.2cm]{geometry} \includegraphics[width=0.5\linewidth]{a1}"
                "\n" r"\newcommand\x[1]{#1} \vspace{3pt}")
        self.assertEqual(stray_digits(text), [])


class PaperLintTest(unittest.TestCase):
    def test_no_typed_numbers(self):
        for path in support.hand_written_tex():
            with open(path, encoding="utf-8") as handle:
                found = stray_digits(handle.read())
            self.assertEqual(found, [], f"{os.path.relpath(path, support.REPO)}: a digit outside "
                             f"the allowed contexts (write it as \\R{{key}}, see test_lint.py)")

    def _keys_used(self):
        out, _ = support.generated()
        used = {}
        sources = support.hand_written_tex() + [os.path.join(out, f) for f in os.listdir(out)
                                                if f.endswith(".tex") and f != "values.tex"]
        for path in sources:
            with open(path, encoding="utf-8") as handle:
                text = _COMMENT.sub("", handle.read())
                for key in _KEY.findall(text):
                    if "#" not in key:  # a macro's parameter (preamble.tex), not a key
                        used.setdefault(key, os.path.basename(path))
                for _, suite in _RUNS.findall(text):
                    if "#" not in suite:
                        used.setdefault(f"runs.suite.{suite}", os.path.basename(path))
        return used

    def test_every_key_is_generated(self):
        _, provenance = support.generated()
        undefined = {k: f for k, f in self._keys_used().items() if k not in provenance}
        self.assertEqual(undefined, {}, "keys the text uses that generate.py does not define")

    def test_every_key_resolves_to_validated_rows(self):
        _, provenance = support.generated()
        for key in self._keys_used():
            entry = provenance.get(key, {})
            for group in entry.get("groups", []):
                self.assertTrue(group, key)
                for file, line in group:
                    cells = read_back_row(file, line)
                    self.assertTrue(usable(cells), f"{key}: {file}:{line} is not validated")

    def test_committed_results_measure_every_key_the_text_uses(self):
        if "PAPER_RESULTS" in os.environ:
            self.skipTest("partial (smoke) tables may lack some figures")
        _, provenance = support.generated()
        missing = [k for k in self._keys_used() if provenance.get(k, {}).get("operation")
                   == "not_measured"]
        self.assertEqual(missing, [])


@functools.lru_cache(maxsize=None)
def _lines(path):
    with open(path, newline="", encoding="utf-8-sig") as handle:
        return list(csv.reader(handle))


def read_back_row(file, line):
    """The row at file:line, read with the csv module alone (not the generator's reader)."""
    lines = _lines(os.path.join(support.results_dir(), file))
    return dict(zip(lines[0], lines[line - 1]))


def usable(cells):
    """Validated, and not marked as checked by nothing."""
    return cells.get("validated") == "true" and cells.get("check", "x") not in ("", "none")


if __name__ == "__main__":
    unittest.main()
