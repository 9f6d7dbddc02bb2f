"""The harness's registry of suites and structures (results/registry.json), as Python objects.

`spatialbench` writes results/registry.json on every run (and `spatialbench list --json` prints
it).  Everything the figures need to know about a suite or a structure comes from it, never
from names written into the plotting code:

* a suite's description, its `baseline` (the structure time ratios and speed-ups are taken
  against), its `targets` (the issue's goals, drawn as lines), `series_params` (params that name
  a curve rather than a figure), and for scene pipelines `stages`, `total_stage` and
  `once_stages`;
* a structure's `family` (variants of one structure, drawn in one hue), `kind` (library, peer
  or oracle; other kinds such as "example" are accepted and treated like library), `bv` (its
  volume type, where it has one; else settings.bv), `settings` (builder, bv, strategy, ...) and
  `complexity` (operation -> theory key such as "n log n"; "*" is the default for operations
  not listed).  Fields the plots do not use (suites, size_class, max_n, ...) are ignored.

Registry.from_dict checks the schema and raises RegistryError (with the file name) on anything
it cannot use; fields a version-1 registry may leave out get empty defaults.
"""

import collections
from dataclasses import dataclass, field

SCHEMA_VERSION = 1


class RegistryError(Exception):
    """results/registry.json is missing or malformed; the message names the file."""


@dataclass(frozen=True)
class Target:
    metric: str  # speedup | steps_per_second | ...
    structure: str  # "" when the target is about every participant
    workload: str
    n: int
    value: float
    label: str = ""


@dataclass(frozen=True)
class Suite:
    name: str
    table: str = ""
    description: str = ""
    baseline: str = ""
    targets: tuple = ()
    series_params: tuple = ()
    stages: tuple = ()
    total_stage: str = ""
    once_stages: tuple = ()

    def targets_for(self, metric):
        return [target for target in self.targets if target.metric == metric]


@dataclass(frozen=True)
class Structure:
    name: str
    family: str
    kind: str = "library"  # library | peer | oracle (| example ...)
    bv: str = ""  # the volume type the structure is built with, "" if none or several
    library: str = ""
    description: str = ""
    settings: dict = field(default_factory=dict)
    complexity: dict = field(default_factory=dict)


class Registry:
    """Suites and structures in the order the harness lists them (the style depends on it)."""

    def __init__(self, suites, structures, generator="", source="registry.json"):
        self.suites = collections.OrderedDict((suite.name, suite) for suite in suites)
        self.structures = collections.OrderedDict((s.name, s) for s in structures)
        self.generator = generator
        self.source = source

    # ---------------------------------------------------------------- lookups

    def suite(self, name):
        return self.suites.get(name)

    def structure(self, name):
        return self.structures.get(name)

    def settings(self, name):
        structure = self.structures.get(name)
        return structure.settings if structure else {}

    def bv(self, name):
        structure = self.structures.get(name)
        return structure.bv if structure else ""

    def kind(self, name):
        structure = self.structures.get(name)
        return structure.kind if structure else ""

    def baseline(self, suite):
        entry = self.suites.get(suite)
        return entry.baseline if entry else ""

    def series_params(self, suite):
        entry = self.suites.get(suite)
        return entry.series_params if entry else ()

    def families(self):
        """{family: [structure names, registry order]}, families in order of first appearance."""
        out = collections.OrderedDict()
        for structure in self.structures.values():
            out.setdefault(structure.family, []).append(structure.name)
        return out

    def theory_for(self, operation, metric, structure):
        """The theory key of one series: the structure's entry for `operation`; for an
        operation it does not list, its "build" entry when the metric is build_time, else its
        "*" default.  None for a structure the registry lacks (or without any entry)."""
        entry = self.structures.get(structure)
        if entry is None:
            return None
        complexity = entry.complexity
        if operation in complexity:
            return complexity[operation]
        if metric == "build_time" and "build" in complexity:
            return complexity["build"]
        return complexity.get("*")

    def reference_theory(self, suite, operation, metric, structures):
        """The theory a complexity panel's grey line follows: the suite baseline's, else the
        most common one among the panel's non-oracle structures (a linear-scan oracle's
        trivially fast "build" must not turn an n log n line into an n line)."""
        baseline = self.baseline(suite)
        if baseline in self.structures:
            theory = self.theory_for(operation, metric, baseline)
            if theory is not None:
                return theory
        for pool in ([s for s in structures if self.kind(s) != "oracle"], list(structures)):
            counts = collections.Counter(self.theory_for(operation, metric, s) for s in pool)
            counts.pop(None, None)
            if counts:
                return max(counts, key=lambda key: (counts[key], key))
        return None

    # ---------------------------------------------------------------- parsing

    @classmethod
    def from_dict(cls, data, source="registry.json"):
        def fail(what):
            raise RegistryError(f"{source}: {what}")

        if not isinstance(data, dict):
            fail("not a JSON object")
        if data.get("schema_version") != SCHEMA_VERSION:
            fail(f"schema_version is {data.get('schema_version')!r}, expected {SCHEMA_VERSION}")
        for key in ("suites", "structures"):
            if not isinstance(data.get(key), list):
                fail(f"'{key}' must be a list")

        def text(entry, key, where, default=""):
            value = entry.get(key, default)
            if not isinstance(value, str):
                fail(f"{where}: '{key}' must be a string")
            return value

        def texts(entry, key, where):
            value = entry.get(key, [])
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                fail(f"{where}: '{key}' must be a list of strings")
            return tuple(value)

        def named_entries(what, noun):
            """(name, where, entry) of each entry of data[what]; fails on a missing or
            repeated name."""
            seen = set()
            for index, entry in enumerate(data[what]):
                if not isinstance(entry, dict) or not isinstance(entry.get("name"), str) \
                        or not entry["name"]:
                    fail(f"{what}[{index}] has no 'name'")
                name = entry["name"]
                where = f"{noun} '{name}'"
                if name in seen:
                    fail(f"{where} is listed twice")
                seen.add(name)
                yield name, where, entry

        def number(entry, key, where):
            value = entry.get(key)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                fail(f"{where}: '{key}' must be a number")
            return value

        suites = []
        for name, where, entry in named_entries("suites", "suite"):
            targets = entry.get("targets", [])
            if not isinstance(targets, list) or not all(isinstance(t, dict) for t in targets):
                fail(f"{where}: 'targets' must be a list of objects")
            suites.append(Suite(
                name=name, table=text(entry, "table", where),
                description=text(entry, "description", where),
                baseline=text(entry, "baseline", where),
                targets=tuple(Target(metric=text(t, "metric", f"{where} target"),
                                     structure=text(t, "structure", f"{where} target"),
                                     workload=text(t, "workload", f"{where} target"),
                                     n=int(number(t, "n", f"{where} target")),
                                     value=float(number(t, "value", f"{where} target")),
                                     label=text(t, "label", f"{where} target"))
                              for t in targets),
                series_params=texts(entry, "series_params", where),
                stages=texts(entry, "stages", where),
                total_stage=text(entry, "total_stage", where),
                once_stages=texts(entry, "once_stages", where)))

        structures = []
        for name, where, entry in named_entries("structures", "structure"):
            kind = text(entry, "kind", where, "library") or "library"
            mappings = {}
            for key, allowed in (("settings", (str, int, float, bool)), ("complexity", (str,))):
                value = entry.get(key, {})
                if not isinstance(value, dict) or not all(
                        isinstance(k, str) and isinstance(v, allowed) for k, v in value.items()):
                    fail(f"{where}: '{key}' must map strings to "
                         + ("strings" if key == "complexity" else "scalars"))
                mappings[key] = {k: (str(v).lower() if isinstance(v, bool) else str(v))
                                 for k, v in value.items()}
            structures.append(Structure(
                name=name, family=text(entry, "family", where, name) or name, kind=kind,
                bv=text(entry, "bv", where) or mappings["settings"].get("bv", ""),
                library=text(entry, "library", where), description=text(entry, "description", where),
                settings=mappings["settings"], complexity=mappings["complexity"]))
        generator = data.get("generator", "")
        return cls(suites, structures, generator if isinstance(generator, str) else "", source)
