#!/usr/bin/python3
"""scikit-learn side of the parity test (tests/training/sklearn_parity_test.cpp) and of bench/train_sklearn.py.

Input: a CSV of standardised features (columns: label, f0, f1, ...; label an integer class index) and a JSON file
with the splits the C++ side used ({"splits": [{"train": [...], "test": [...]}, ...], "C": [...], "gamma": [...],
"checks": [[C, gamma], ...]}). Output JSON: per check, SVC(C, gamma, kernel='rbf') trained on split 0's train
part, its predictions on split 0's test part; and GridSearchCV over the grid with exactly those splits.
"""
import argparse
import csv
import json
import time

import numpy as np
from sklearn.model_selection import GridSearchCV
from sklearn.svm import SVC


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--features", required=True)
    ap.add_argument("--splits", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    with open(args.features) as f:
        rows = list(csv.reader(f))
    X = np.array([[float(v) for v in r[1:]] for r in rows[1:]])
    y = np.array([int(r[0]) for r in rows[1:]])
    with open(args.splits) as f:
        spec = json.load(f)
    cv = [(np.array(s["train"]), np.array(s["test"])) for s in spec["splits"]]
    out = {"checks": []}
    train, test = cv[0]
    for C, gamma in spec.get("checks", []):
        svc = SVC(C=C, gamma=gamma, kernel="rbf").fit(X[train], y[train])
        out["checks"].append({"C": C, "gamma": gamma, "predicted": svc.predict(X[test]).tolist(),
                              "n_support": svc.n_support_.tolist()})
    t0 = time.perf_counter()
    gs = GridSearchCV(SVC(kernel="rbf"), {"C": spec["C"], "gamma": spec["gamma"]}, cv=cv, scoring="accuracy",
                      n_jobs=spec.get("n_jobs", 1), refit=False)
    gs.fit(X, y)
    out["grid_seconds"] = time.perf_counter() - t0
    out["best_C"] = gs.best_params_["C"]
    out["best_gamma"] = gs.best_params_["gamma"]
    out["best_score"] = gs.best_score_
    # ParameterGrid order: C outer, gamma inner.
    out["mean_test_score"] = gs.cv_results_["mean_test_score"].tolist()
    with open(args.out, "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
