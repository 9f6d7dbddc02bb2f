"""Finding the rows a quote needs among the usable rows of every table.

Rows of one key from several tables or runs (repeated runs, head-to-head reruns) are all
returned; the quote reduces them to their median (reduce.py), and its provenance lists them."""

from collections import defaultdict


class Rows:
    def __init__(self, tables):
        self.all = [row for table in tables for row in table.rows]
        self.usable = [row for row in self.all if row.usable]
        self._by_suite = defaultdict(list)  # most finds name a suite: search only its rows
        for row in self.usable:
            self._by_suite[row["suite"]].append(row)

    def find(self, **key):
        """Usable rows matching every given column (n compared as a number; bv '-' = '')."""
        def matches(row):
            for column, wanted in key.items():
                if column == "n":
                    if row.n != int(wanted):
                        return False
                elif column == "bv":
                    if row["bv"].replace("-", "") != wanted.replace("-", ""):
                        return False
                elif row[column] != wanted:
                    return False
            return True
        candidates = self._by_suite.get(key["suite"], []) if "suite" in key else self.usable
        return [row for row in candidates if matches(row)]

    def values_of(self, column, **key):
        """Distinct values of `column` among the rows matching key, in first-seen order."""
        seen = {}
        for row in self.find(**key):
            seen.setdefault(row[column] if column != "n" else row.n, None)
        return list(seen)

    def largest_n(self, **key):
        ns = [row.n for row in self.find(**key)]
        return max(ns) if ns else None

    def by(self, column, **key):
        """{value of column: rows} for the rows matching key."""
        groups = defaultdict(list)
        for row in self.find(**key):
            groups[row[column] if column != "n" else row.n].append(row)
        return dict(groups)
