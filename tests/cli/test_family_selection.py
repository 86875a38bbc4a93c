"""Choosing the feature family inside the nested CV (bench/family_selection.py): `wish train` writes, per family of
its comparison, the nested CV's score and the inner search's best validation accuracy for every outer fold, on the
same folds for every family; the script's per-fold choice is exact on a report built so that one family's inner
search always wins (its nested-CV mean comes back) and follows the inner scores fold by fold otherwise.
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

from wish_cli import SOURCE_DIR, run

DESCRIPTORS = os.path.join(SOURCE_DIR, "data", "models", "demo-descriptors.csv")
SCRIPT = os.path.join(SOURCE_DIR, "bench", "family_selection.py")


def select(*reports):
    out = subprocess.run([sys.executable, SCRIPT, *[f"r{i}={p}" for i, p in enumerate(reports)]],
                         capture_output=True, text=True, check=True).stdout
    rows = [line.split("|")[1:-1] for line in out.splitlines() if line.startswith("| r")]
    return [[cell.strip() for cell in row] for row in rows]


class FamilySelection(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-family-selection-")
        cls.report_path = os.path.join(cls.tmp, "report.json")
        run("train", DESCRIPTORS, "--out", os.path.join(cls.tmp, "m.json"), "--report", cls.report_path,
            "--nested-repeats", "1", "--quiet")
        with open(cls.report_path) as f:
            cls.report = json.load(f)

    def test_every_family_reports_the_same_folds(self):
        folds = self.report["nested_cv"]["folds"]
        self.assertEqual(len(self.report["nested_cv"]["inner_best_scores"]), folds)
        families = {row["family"]: row for row in self.report["comparison"]}
        self.assertEqual(set(families), {"invariants", "global", "combined"})
        for family, row in families.items():
            self.assertEqual(len(row["nested_cv_scores"]), folds, family)
            self.assertEqual(len(row["nested_cv_inner_best_scores"]), folds, family)
            self.assertAlmostEqual(sum(row["nested_cv_scores"]) / folds, row["nested_cv_mean"], places=12)
            for inner in row["nested_cv_inner_best_scores"]:
                self.assertTrue(0 < inner <= 1, family)
        own = families[self.report["features"]["family"]]
        self.assertEqual(own["nested_cv_inner_best_scores"], self.report["nested_cv"]["inner_best_scores"])

    def test_the_choice_follows_the_inner_scores_fold_by_fold(self):
        rows = {row["family"]: row for row in self.report["comparison"]}
        folds = len(rows["combined"]["nested_cv_scores"])
        for winner in ("invariants", "global", "combined"):
            forged = json.loads(json.dumps(self.report))
            for row in forged["comparison"]:
                row["nested_cv_inner_best_scores"] = [1.0 if row["family"] == winner else 0.5] * folds
            path = os.path.join(self.tmp, f"forged-{winner}.json")
            with open(path, "w") as f:
                json.dump(forged, f)
            chosen = float(select(path)[0][4])
            self.assertAlmostEqual(chosen, round(rows[winner]["nested_cv_mean"], 3), places=3, msg=winner)
        # Alternate winners: fold k goes to global when k is even, else to invariants.
        forged = json.loads(json.dumps(self.report))
        for row in forged["comparison"]:
            row["nested_cv_inner_best_scores"] = [
                1.0 if row["family"] == ("global" if k % 2 == 0 else "invariants") else 0.5 for k in range(folds)]
        path = os.path.join(self.tmp, "forged-alternate.json")
        with open(path, "w") as f:
            json.dump(forged, f)
        expected = sum(rows["global" if k % 2 == 0 else "invariants"]["nested_cv_scores"][k] for k in range(folds)) / folds
        row = select(path)[0]
        self.assertAlmostEqual(float(row[4]), round(expected, 3), places=3)
        self.assertEqual(row[5], f"0/{(folds + 1) // 2}/{folds // 2}")


if __name__ == "__main__":
    unittest.main()
