#!/usr/bin/env python3
"""Nested-CV accuracy of choosing the feature family per training set (issues 37 and 38: "the default is what
classifies best"), from the JSON reports `wish train ... --report R.json` writes (with its family comparison).

Every family of the comparison is trained with the same seed, so its nested CV runs on the same outer folds. In each
outer fold the policy "choose" takes the family whose inner grid search had the best validation accuracy
(nested_cv_inner_best_scores: computed on that fold's training rows only, so the choice stays inside the fold; ties
to the order combined, global, invariants) and scores that family's model on the fold's held-out rows. Its mean over
the folds is an honest nested-CV estimate of `wish train` choosing the family itself.

  bench/family_selection.py NAME=REPORT.json ...   prints a markdown table and the means over the reports
"""
import json
import sys

ORDER = ["combined", "global", "invariants"]  # the tie order: the current default first


def scores(report_path):
    with open(report_path, encoding="utf-8") as f:
        report = json.load(f)
    rows = {row["family"]: row for row in report.get("comparison", [])}
    missing = [family for family in ORDER if family not in rows or "nested_cv_inner_best_scores" not in rows[family]]
    if missing:
        raise SystemExit(f"{report_path}: no per-fold comparison for {', '.join(missing)} (train without --no-compare, "
                         "on a build that writes nested_cv_inner_best_scores)")
    folds = len(rows[ORDER[0]]["nested_cv_scores"])
    if any(len(rows[f]["nested_cv_scores"]) != folds or len(rows[f]["nested_cv_inner_best_scores"]) != folds
           for f in ORDER):
        raise SystemExit(f"{report_path}: the families ran different numbers of outer folds")
    chosen, picks = [], {family: 0 for family in ORDER}
    for k in range(folds):
        best = max(ORDER, key=lambda f: (rows[f]["nested_cv_inner_best_scores"][k], -ORDER.index(f)))
        picks[best] += 1
        chosen.append(rows[best]["nested_cv_scores"][k])
    fixed = {f: sum(rows[f]["nested_cv_scores"]) / folds for f in ORDER}
    return fixed, sum(chosen) / folds, picks


def main(argv):
    if not argv or any("=" not in a for a in argv):
        print(__doc__, file=sys.stderr)
        return 2
    print("| set | ξ | global | combined | chosen per fold | picks (combined/global/ξ) |")
    print("|---|---|---|---|---|---|")
    totals = {"invariants": 0.0, "global": 0.0, "combined": 0.0, "chosen": 0.0}
    for arg in argv:
        name, path = arg.split("=", 1)
        fixed, chosen, picks = scores(path)
        for f in ORDER:
            totals[f] += fixed[f]
        totals["chosen"] += chosen
        print(f"| {name} | {fixed['invariants']:.3f} | {fixed['global']:.3f} | {fixed['combined']:.3f} | {chosen:.3f} | "
              f"{picks['combined']}/{picks['global']}/{picks['invariants']} |")
    n = len(argv)
    print(f"| mean of {n} | {totals['invariants'] / n:.3f} | {totals['global'] / n:.3f} | {totals['combined'] / n:.3f} | "
          f"{totals['chosen'] / n:.3f} | |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
