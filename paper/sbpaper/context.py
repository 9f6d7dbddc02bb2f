"""What every section generator gets: the usable rows, the book of quoted values, the output
directory, the registry, and the set of suites this run measured (flags.tex)."""

import json
import os
from dataclasses import dataclass, field

from . import latex
from .select import Rows


@dataclass
class Context:
    rows: Rows
    book: object
    out_dir: str
    registry: dict
    tables: list
    measured: set = field(default_factory=set)

    def table(self, file_name, text):
        latex.write(self.out_dir, file_name, text)

    def suite_measured(self, suite, measured):
        if measured:
            self.measured.add(suite)
        return measured


def read_registry(results_dir):
    path = os.path.join(results_dir, "registry.json")
    try:
        with open(path, encoding="utf-8") as handle:
            return json.load(handle)
    except FileNotFoundError:
        return {"suites": [], "structures": []}
