"""--formats and --families (spatialplots/formats.py, cli.py): the same figure code writes a
vector PDF beside or instead of the PNG, and only the named families draw."""

import os

from . import support
from .support import write_csv
from .test_scenes import REGISTRY
from .test_collide import scenes_rows
from spatialplots import formats


class FormatsTest(support.ResultsTestCase):
    REGISTRY = REGISTRY

    def tearDown(self):
        formats.choose(["png"])  # the run-wide choice must not leak into other tests
        super().tearDown()

    def files(self):
        return sorted(os.listdir(self.out))

    def test_pdf_beside_png(self):
        write_csv(self.results, "scenes.csv", scenes_rows())
        code, _, stderr = self.plot("--formats", "png,pdf")
        self.assertEqual(code, 0, stderr)
        self.assertEqual(self.files(), ["scenes.pdf", "scenes.png", "scenes_summary.pdf",
                                        "scenes_summary.png"])
        with open(os.path.join(self.out, "scenes.pdf"), "rb") as handle:
            self.assertEqual(handle.read(5), b"%PDF-")

    def test_pdf_only_and_family_filter(self):
        write_csv(self.results, "scenes.csv", scenes_rows())
        code, _, stderr = self.plot("--formats", "pdf", "--families", "scenes")
        self.assertEqual(code, 0, stderr)
        self.assertEqual(self.files(), ["scenes.pdf"])
        code, _, _ = self.plot("--formats", "pdf", "--families", "collide")
        self.assertEqual(self.files(), ["scenes.pdf"])  # scenes not drawn again, nothing else

    def test_unknown_format_is_refused(self):
        with self.assertRaises(SystemExit):
            self.plot("--formats", "svg")
