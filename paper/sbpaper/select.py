"""Finding the rows a quote needs among the usable rows of every table.

Rows of one key from several tables or runs (repeated runs, head-to-head reruns) are all
returned; the quote reduces them to their median (reduce.py), and its provenance lists them."""

from collections import defaultdict


def _settings_by_structure(registry):
    return {entry.get("name"): set(entry.get("settings", {})) for entry in (registry or {}).get("structures", [])}


def is_swept_configuration(row, settings):
    """A row of a tuning sweep's configuration (its params name a registry setting of its
    structure, e.g. k=10;bucket_size=32): the paper reports those through the best_peer_ratio
    rows only, so the other sections see each structure at its default, as at every size."""
    if row["metric"] == "best_peer_ratio":
        return False
    named = {item.split("=", 1)[0] for item in row["params"].split(";") if item}
    return bool(named & settings.get(row["structure"], set()))


class Rows:
    def __init__(self, tables, registry=None):
        settings = _settings_by_structure(registry)
        self.all = [row for table in tables for row in table.rows]
        self.usable = [row for row in self.all if row.usable and not is_swept_configuration(row, settings)]
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
