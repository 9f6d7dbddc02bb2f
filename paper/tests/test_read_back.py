"""Every generated number equals what its rows say: each value in provenance.json is recomputed
from the CSV lines it names (read here with the csv module and recomputed here, not by the
generator's code), and the number shown in values.tex is that value rounded as displayed."""

import math
import os
import re
import statistics
import unittest

from tests import support
from tests.test_lint import read_back_row, usable


def recompute(entry):
    groups = [[float(read_back_row(f, line)["value"]) for f, line in g] for g in entry["groups"]]
    sizes = [int(float(read_back_row(*g[0])["n"])) for g in entry["groups"]]
    values = [statistics.median(g) for g in groups]
    operation = entry["operation"]
    if operation in ("value", "n"):
        return sizes[0] if operation == "n" else values[0]
    if operation == "ratio":
        return values[0] / values[1]
    if operation == "share":
        return sum(values[1:]) / values[0]
    if operation == "exponent":
        slope = statistics.linear_regression([math.log(n) for n in sizes],
                                             [math.log(v) for v in values]).slope
        return slope
    if operation == "geomean":
        return statistics.geometric_mean(values)
    return {"min": min, "max": max, "sum": sum, "count": len,
            "mean": statistics.fmean}[operation](values)


def shown_number(number_text):
    """The number the PDF shows: '65\\,536' -> 65536, '10^{6}' -> 1e6."""
    power = re.fullmatch(r"10\^\{(\d+)\}", number_text)
    if power:
        return 10.0 ** int(power.group(1)), 0.0
    plain = number_text.replace(r"\,", "")
    decimals = len(plain.split(".")[1]) if "." in plain else 0
    return float(plain), 0.5 * 10.0 ** -decimals


class ReadBackTest(unittest.TestCase):
    def test_values_equal_their_rows(self):
        _, provenance = support.generated()
        checked = 0
        for key, entry in provenance.items():
            if "groups" not in entry:
                continue
            expected = recompute(entry)
            self.assertTrue(math.isclose(expected, entry["value"], rel_tol=1e-9), key)
            shown, half_unit = shown_number(entry["number"])
            self.assertLessEqual(abs(shown - expected * entry["scale"]),
                                 half_unit * (1 + 1e-9) + 1e-12 * abs(shown),
                                 f"{key}: shows {entry['number']}, the rows give "
                                 f"{expected * entry['scale']}")
            self.assertIn(entry["number"], entry["text"], key)
            checked += 1
        self.assertGreater(checked, 0)

    def test_tallies_equal_a_recount(self):
        import csv
        _, provenance = support.generated()
        for key, entry in provenance.items():
            if entry["operation"] != "tally":
                continue
            count = 0
            for file in entry["files"]:
                with open(os.path.join(support.results_dir(), file), newline="") as handle:
                    reader = csv.DictReader(handle)
                    has_check = "check" in reader.fieldnames
                    for cells in reader:
                        if entry["run_id"] not in (None, cells.get("run_id")):
                            continue
                        count += {"rows": True, "no_check_column": not has_check,
                                  "check_none": has_check and cells["check"] in ("", "none"),
                                  "validated_false": cells["validated"] != "true",
                                  "usable": usable(cells) if has_check else
                                  cells["validated"] == "true"}[entry["criterion"]]
            self.assertEqual(count, entry["value"], key)

    def test_values_tex_holds_every_key(self):
        out, provenance = support.generated()
        with open(os.path.join(out, "values.tex"), encoding="utf-8") as handle:
            defined = re.findall(r"^\\sbvalue\{([^{}]*)\}", handle.read(), re.MULTILINE)
        self.assertEqual(sorted(defined), sorted(provenance))


if __name__ == "__main__":
    unittest.main()
