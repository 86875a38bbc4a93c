"""wish-client plot: t-SNE, ξ(l) spectrum, confusion matrix — files are written and are real PNG/SVG."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import tempfile
import unittest
from pathlib import Path

import numpy as np

from wish_client.cli import main
from wish_client.plots import find_confusion, match_labels

CLASSES = ["neuron", "astrocyte", "microglia"]


def run_cli(*argv: str) -> int:
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return main(list(argv))


class PlotTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls) -> None:
        cls.tmp = Path(tempfile.mkdtemp(prefix="wish-plots-"))
        rng = np.random.default_rng(3)
        cls.csv = cls.tmp / "describe.csv"
        cls.labels = cls.tmp / "labels.csv"
        with cls.csv.open("w", newline="") as f, cls.labels.open("w", newline="") as g:
            w, wl = csv.writer(f), csv.writer(g)
            w.writerow(["file", "n_vertices", "fit_error_mean", "fit_error_max"] + [f"xi_{l}" for l in range(9)])
            wl.writerow(["file", "label"])
            for c, name in enumerate(CLASSES):
                for i in range(12):
                    xi = (1 + c) * np.exp(-(1 + 0.5 * c) * np.arange(9)) * np.exp(rng.normal(0, 0.2, 9))
                    file = f"data/{name}/cell{i}.obj"
                    w.writerow([file, 3000, 0.01, 0.05] + list(xi))
                    wl.writerow([Path(file).name, name])

    def assert_image(self, path: Path) -> None:
        data = path.read_bytes()
        if path.suffix == ".png":
            self.assertEqual(data[:8], b"\x89PNG\r\n\x1a\n")
        else:
            self.assertIn(b"<svg", data[:2000])

    def test_tsne_png_with_labels_file(self) -> None:
        out = self.tmp / "tsne.png"
        self.assertEqual(run_cli("plot", "tsne", str(self.csv), "--labels", str(self.labels), "--out", str(out)), 0)
        self.assert_image(out)

    def test_spectrum_svg_from_folders(self) -> None:
        out = self.tmp / "spectrum.svg"
        self.assertEqual(run_cli("plot", "spectrum", str(self.csv), "--labels-from-folder", "--normalise",
                                 "--out", str(out)), 0)
        self.assert_image(out)

    def test_confusion_from_report_and_from_predictions(self) -> None:
        report = self.tmp / "report.json"
        report.write_text(json.dumps({"test": {"classes": CLASSES, "confusion_matrix": [[5, 1, 0], [0, 4, 2],
                                                                                        [1, 0, 6]]}}))
        out = self.tmp / "confusion.png"
        self.assertEqual(run_cli("plot", "confusion", "--report", str(report), "--out", str(out)), 0)
        self.assert_image(out)
        pred = self.tmp / "results.csv"
        pred.write_text("file,status,label\na/cell0.obj,ok,neuron\na/cell1.obj,ok,astrocyte\nx.obj,error,\n")
        truth = self.tmp / "truth.csv"
        truth.write_text("file,label\ncell0.obj,neuron\ncell1.obj,neuron\n")
        out2 = self.tmp / "confusion2.svg"
        self.assertEqual(run_cli("plot", "confusion", "--predicted", str(pred), "--labels", str(truth),
                                 "--normalise", "--out", str(out2)), 0)
        self.assert_image(out2)

    def test_helpers_and_errors(self) -> None:
        self.assertEqual(match_labels(["a/b/c.obj", "x.ply", "q"], {"c.obj": "n", "x": "m"}), ["n", "m", None])
        classes, m = find_confusion({"confusion_matrix": {"a": {"a": 2, "b": 1}, "b": {"a": 0, "b": 3}}})
        self.assertEqual((classes, m), (["a", "b"], [[2, 1], [0, 3]]))
        self.assertEqual(run_cli("plot", "tsne", str(self.csv), "--out", str(self.tmp / "x.png")), 2)  # no labels
        self.assertEqual(run_cli("plot", "spectrum", str(self.csv), "--labels-from-folder", "--out",
                                 str(self.tmp / "x.gif")), 2)


if __name__ == "__main__":
    unittest.main()
