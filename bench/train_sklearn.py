#!/usr/bin/python3
"""scikit-learn side of bench/train_bench.cpp: the same training as `wish train` on a descriptor CSV
(file,label,xi_0..xi_L[,g_*]), timed. Features: xi(1..lmax), optional log, StandardScaler fitted on the stratified
80 % training split; GridSearchCV(SVC(kernel='rbf')) over the paper's 13 x 13 grid with StratifiedShuffleSplit
(n_splits, test_size=0.2, fixed seed); refit with probability=True; test accuracy. Prints one JSON object.
"""
import argparse
import csv
import json
import time

import numpy as np
from sklearn.model_selection import GridSearchCV, StratifiedShuffleSplit, train_test_split
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVC


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--lmax", type=int, default=5)
    ap.add_argument("--log", action="store_true")
    ap.add_argument("--splits", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--seed", type=int, default=42)
    args = ap.parse_args()
    with open(args.csv) as f:
        rows = list(csv.DictReader(f))
    X = np.array([[float(r[f"xi_{l}"]) for l in range(1, args.lmax + 1)] for r in rows])
    if args.log:
        X = np.log(np.maximum(X, np.finfo(float).tiny))
    y = np.array([r["label"] for r in rows])
    grid = {"C": [10.0 ** e for e in range(-2, 11)], "gamma": [10.0 ** e for e in range(-9, 4)]}

    t0 = time.perf_counter()
    Xa, Xb, ya, yb = train_test_split(X, y, test_size=0.2, stratify=y, random_state=args.seed)
    scaler = StandardScaler().fit(Xa)
    Xa, Xb = scaler.transform(Xa), scaler.transform(Xb)
    cv = StratifiedShuffleSplit(n_splits=args.splits, test_size=0.2, random_state=args.seed + 1)
    t1 = time.perf_counter()
    gs = GridSearchCV(SVC(kernel="rbf"), grid, cv=cv, scoring="accuracy", n_jobs=args.jobs, refit=False).fit(Xa, ya)
    t2 = time.perf_counter()
    svc = SVC(kernel="rbf", probability=True, random_state=args.seed, **gs.best_params_).fit(Xa, ya)
    test_accuracy = float((svc.predict(Xb) == yb).mean())
    t3 = time.perf_counter()
    print(json.dumps({"samples": len(y), "features": X.shape[1], "best_C": gs.best_params_["C"],
                      "best_gamma": gs.best_params_["gamma"], "grid_score": gs.best_score_,
                      "test_accuracy": test_accuracy, "grid_seconds": t2 - t1, "train_seconds": t3 - t0}))


if __name__ == "__main__":
    main()
