#!/usr/bin/python3
"""scikit-learn side of bench/train_scale_bench.cpp (issues 25 and 40): the search of `wish train` on the SAME rows,
hold-out split and validation splits as the C++ side (passed in a JSON file), timed.
Features: xi(1..lmax) of the descriptor CSV, log, StandardScaler fitted on the hold-out training rows; the paper's
13 x 13 grid over SVC(kernel='rbf', max_iter=10**7) (max_iter as libsvm 3.24's own cap, which scikit-learn's libsvm
fork lifts by default), searched with
  --search grid:    GridSearchCV, every cell on the given splits;
  --search halving: HalvingGridSearchCV (successive halving, resource = samples, factor 3, min_resources 'exhaust',
                    its defaults) on the same splits, each subsampled by scikit-learn at each iteration;
then refit with probability=True at the best cell on all hold-out training rows; test accuracy on the hold-out rows.
Prints one JSON object.
"""
import argparse
import csv
import json
import time
import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning
from sklearn.experimental import enable_halving_search_cv  # noqa: F401 (registers HalvingGridSearchCV)
from sklearn.model_selection import GridSearchCV, HalvingGridSearchCV
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVC


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("splits", help="JSON: labels, holdout {train, test}, grid_splits [{train, test}] (row indices)")
    ap.add_argument("--lmax", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--seed", type=int, default=44)
    ap.add_argument("--search", choices=["grid", "halving"], default="grid")
    args = ap.parse_args()
    with open(args.csv) as f:
        rows = list(csv.DictReader(f))
    with open(args.splits) as f:
        spec = json.load(f)
    X = np.log(np.maximum(np.array([[float(r[f"xi_{l}"]) for l in range(1, args.lmax + 1)] for r in rows]),
                          np.finfo(float).tiny))
    y = np.array(spec["labels"])
    tr, te = np.array(spec["holdout"]["train"]), np.array(spec["holdout"]["test"])
    grid = {"C": [10.0 ** e for e in range(-2, 11)], "gamma": [10.0 ** e for e in range(-9, 4)]}
    cv = [(np.array(s["train"]), np.array(s["test"])) for s in spec["grid_splits"]]

    t0 = time.perf_counter()
    scaler = StandardScaler().fit(X[tr])
    Xa, Xb = scaler.transform(X[tr]), scaler.transform(X[te])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ConvergenceWarning)
        if args.search == "halving":
            gs = HalvingGridSearchCV(SVC(kernel="rbf", max_iter=10**7), grid, cv=cv, scoring="accuracy", factor=3,
                                     n_jobs=args.jobs, refit=False, random_state=args.seed,
                                     return_train_score=False).fit(Xa, y[tr])
        else:
            gs = GridSearchCV(SVC(kernel="rbf", max_iter=10**7), grid, cv=cv, scoring="accuracy", n_jobs=args.jobs,
                              refit=False).fit(Xa, y[tr])
    t1 = time.perf_counter()
    svc = SVC(kernel="rbf", probability=True, random_state=args.seed, **gs.best_params_).fit(Xa, y[tr])
    test_accuracy = float((svc.predict(Xb) == y[te]).mean())
    t2 = time.perf_counter()
    capped = sum(1 for w in caught if issubclass(w.category, ConvergenceWarning))
    out = {"samples": len(y), "search": args.search, "best_C": gs.best_params_["C"],
           "best_gamma": gs.best_params_["gamma"], "grid_score": float(gs.best_score_), "test_accuracy": test_accuracy,
           "grid_seconds": t1 - t0, "train_seconds": t2 - t0, "capped_fits_seen": capped,
           "fits": int(len(gs.cv_results_["params"]) * len(cv))}
    if args.search == "halving":
        out["n_resources"] = [int(r) for r in gs.n_resources_]
        out["n_candidates"] = [int(c) for c in gs.n_candidates_]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
