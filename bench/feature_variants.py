#!/usr/bin/python3
"""Nested-CV accuracy of feature variants on raw descriptors dumped by descriptor_accuracy_bench --dump-descriptors
(issue 25 item 1: which descriptor recipe closes the gap between xi alone, global and combined).

    /usr/bin/python3 bench/feature_variants.py DUMP.csv [DUMP.csv ...] [--variants a,b,...] [--jobs J]

Protocol as the project's nested_cross_validation (training.hpp): outer stratified 5-fold repeated twice, z-score
fitted on the outer training fold, inner grid search over 5 stratified shuffle splits (validation 0.2) on the
paper's grid C 1e-2..1e10 x gamma 1e-9..1e3 (--c-range / --gamma-range narrow it: large C makes libsvm crawl on
overlapping classes), RBF SVM. scikit-learn's (not libsvm-through-the-project's) splits and
tie-breaking, so figures differ from the C++ bench by fold noise; the variants are compared with each other in the
same run on the same splits. Variants (features before the z-score):
  xi_log        log xi(1..L)                             (the current default recipe, xi alone)
  xi_tot        log(xi(l) / sum_l>=1 xi(l)) and log sum   (shape spectrum made scale-free + one size feature)
  xi_tot_nosize log(xi(l) / sum xi) only                  (scale-free spectrum)
  xi_l2         log xi(2..L)                              (drop l = 1)
  global        the 11 global descriptors
  comb          xi_log + global                           (the current combined)
  comb_blk      comb with each family scaled to unit total variance after the z-score (divide by sqrt(dim))
  comb_w        comb with the xi block weighted by w in {1/4, 1/2, 1, 2, 4} after the z-score, w chosen in the
                inner CV (a per-family kernel width)
  comb_tot      xi_tot + global;   comb_tot_blk: the same, block-scaled
  comb_logg     xi_log + log|global| of the positive size features (volume, area, radius)
"""
import argparse
import csv
import sys
from collections import defaultdict

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.model_selection import GridSearchCV, RepeatedStratifiedKFold, StratifiedShuffleSplit
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVC

GLOBAL = ["volume", "area", "equivalent_radius", "sphericity", "elongation", "flatness", "axis_ratio",
          "ellipsoid_area_ratio", "mean_curvature_ratio", "abs_mean_curvature_ratio", "concave_fraction"]


class BlockWeight(BaseEstimator, TransformerMixin):
    """Multiplies the first n_xi columns by w and every column of a block by 1/sqrt(block size) when balance."""

    def __init__(self, n_xi=0, w=1.0, balance=False):
        self.n_xi, self.w, self.balance = n_xi, w, balance

    def fit(self, X, y=None):
        return self

    def transform(self, X):
        X = np.array(X, dtype=float)
        n_g = X.shape[1] - self.n_xi
        if self.balance and self.n_xi and n_g:
            X[:, :self.n_xi] /= np.sqrt(self.n_xi)
            X[:, self.n_xi:] /= np.sqrt(n_g)
        X[:, :self.n_xi] *= self.w
        return X


def load(paths):
    sets = defaultdict(list)  # (dataset, method, nu, lmax) -> rows
    for p in paths:
        with open(p) as f:
            reader = csv.DictReader(f)
            top = max(int(c[3:]) for c in reader.fieldnames if c.startswith("xi_"))
            for r in reader:
                # `wish train --save-descriptors` files have no dataset / method / nu / Lmax columns
                key = (r.get("dataset", p.rsplit("/", 1)[-1]), r.get("method", "recipe"), r.get("nu_factor", "-"),
                       int(r.get("lmax", top)))
                sets[key].append(r)
    return sets


def features(rows, variant, lmax):
    xi = np.array([[float(r[f"xi_{l}"]) for l in range(0, lmax + 1)] for r in rows])
    g = np.array([[float(r[f"g_{n}"]) for n in GLOBAL] for r in rows])
    tiny = np.finfo(float).tiny
    logxi = np.log(np.maximum(xi[:, 1:], tiny))
    tot = xi[:, 1:].sum(axis=1, keepdims=True)
    xi_tot = np.hstack([np.log(np.maximum(xi[:, 1:] / tot, tiny)), np.log(tot)])
    xi_tot_nosize = np.log(np.maximum(xi[:, 1:] / tot, tiny))
    logg = g.copy()
    logg[:, :3] = np.log(g[:, :3])
    table = {
        "xi_log": (logxi, 0), "xi_tot": (xi_tot, 0), "xi_tot_nosize": (xi_tot_nosize, 0),
        "xi_l2": (logxi[:, 1:], 0), "global": (g, 0), "global_log": (logg, 0),
        "comb": (np.hstack([logxi, g]), logxi.shape[1]),
        "comb_blk": (np.hstack([logxi, g]), logxi.shape[1]),
        "comb_w": (np.hstack([logxi, g]), logxi.shape[1]),
        "comb_tot": (np.hstack([xi_tot, g]), xi_tot.shape[1]),
        "comb_tot_blk": (np.hstack([xi_tot, g]), xi_tot.shape[1]),
        "comb_tot_w": (np.hstack([xi_tot, g]), xi_tot.shape[1]),
        "comb_logg": (np.hstack([logxi, logg]), logxi.shape[1]),
        "comb_logg_blk": (np.hstack([logxi, logg]), logxi.shape[1]),
        "comb_logg_w": (np.hstack([logxi, logg]), logxi.shape[1]),
    }
    return table[variant]


def nested_cv(X, y, n_xi, variant, jobs, c_range, gamma_range, repeats=2, seed=45):
    grid = {"svc__C": 10.0 ** np.arange(c_range[0], c_range[1] + 1),
            "svc__gamma": 10.0 ** np.arange(gamma_range[0], gamma_range[1] + 1)}
    balance = variant.endswith("_blk")
    if variant.endswith("_w"):
        grid["blk__w"] = [0.25, 0.5, 1.0, 2.0, 4.0]
    pipe = Pipeline([("z", StandardScaler()), ("blk", BlockWeight(n_xi=n_xi, balance=balance)), ("svc", SVC(kernel="rbf"))])
    outer = RepeatedStratifiedKFold(n_splits=min(5, np.bincount(y).min()), n_repeats=repeats, random_state=seed)
    scores = []
    for train, test in outer.split(X, y):
        inner = StratifiedShuffleSplit(n_splits=5, test_size=0.2, random_state=seed)
        gs = GridSearchCV(pipe, grid, cv=inner, n_jobs=jobs)
        gs.fit(X[train], y[train])
        scores.append(gs.score(X[test], y[test]))
    return 100 * np.mean(scores), 100 * np.std(scores)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dumps", nargs="+")
    ap.add_argument("--variants", default="xi_log,xi_tot,xi_l2,global,comb,comb_blk,comb_w,comb_tot,comb_tot_blk")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--lmax", default="")
    ap.add_argument("--methods", default="")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--c-range", type=int, nargs=2, default=[-2, 10])
    ap.add_argument("--gamma-range", type=int, nargs=2, default=[-9, 3])
    a = ap.parse_args()
    variants = a.variants.split(",")
    print("| set | map | ν × | Lmax | n | " + " | ".join(variants) + " |")
    print("|---|---|---|---|---|" + "---|" * len(variants))
    for (dataset, method, nu, lmax), rows in sorted(load(a.dumps).items()):
        if a.lmax and str(lmax) not in a.lmax.split(","):
            continue
        if a.methods and method not in a.methods.split(","):
            continue
        labels = sorted({r["label"] for r in rows})
        y = np.array([labels.index(r["label"]) for r in rows])
        cells = []
        for v in variants:
            X, n_xi = features(rows, v, lmax)
            m, s = nested_cv(X, y, n_xi, v, a.jobs, a.c_range, a.gamma_range, a.repeats)
            cells.append(f"{m:.1f} ± {s:.1f}")
            print(dataset, method, lmax, v, cells[-1], file=sys.stderr, flush=True)
        print(f"| {dataset} | {method} | {nu} | {lmax} | {len(rows)} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
