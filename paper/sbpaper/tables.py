"""The result tables read with their provenance: every row keeps its file and line number, so
a quoted number can be traced back to (and re-read from) the line it came from.

Which rows may be quoted: a row whose `check` column is `none` was verified by nothing and is
never usable.  Tables written before the check column existed are read as the issue says:
usable only when `validated` is true, and counted (Table.without_check) so that the paper can
say how many quoted rows carry no record of what verified them."""

import csv
import glob
import os
from dataclasses import dataclass, field

KEY_COLUMNS = ("suite", "structure", "bv", "workload", "n", "dim", "scalar", "operation",
               "params", "metric")


@dataclass(frozen=True)
class Row:
    file: str  # table file name, e.g. knn.csv
    line: int  # 1-based line in the file (the header is line 1)
    cells: dict = field(hash=False, compare=False)

    def __getitem__(self, column):
        return self.cells.get(column, "")

    @property
    def value(self):
        return float(self.cells["value"])

    @property
    def n(self):
        return int(float(self.cells["n"]))

    @property
    def check(self):
        """The check column, or None for tables written before it existed."""
        return self.cells.get("check")

    @property
    def usable(self):
        """May this row be quoted?  (See the module docstring.)"""
        if self.check is not None and self.check.strip() in ("", "none"):
            return False
        return self.cells.get("validated", "").strip().lower() == "true"


@dataclass
class Table:
    file: str
    has_check: bool
    rows: list


def read_table(path):
    """One table; rows whose value is not a number are kept out (they cannot be quoted)."""
    name = os.path.basename(path)
    with open(path, newline="", encoding="utf-8-sig") as handle:
        reader = csv.reader(handle)
        header = [cell.strip() for cell in next(reader, [])]
        rows = []
        for line_number, cells in enumerate(reader, start=2):
            if len(cells) != len(header):
                continue
            row = Row(name, line_number, dict(zip(header, (c.strip() for c in cells))))
            try:
                row.value
                row.n
            except (KeyError, ValueError):
                continue
            rows.append(row)
    return Table(name, "check" in header, rows)


def read_tables(results_dir):
    """Every *.csv at the top of results_dir, by file name."""
    paths = sorted(glob.glob(os.path.join(results_dir, "*.csv")))
    return [read_table(path) for path in paths]

