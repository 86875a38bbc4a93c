#!/usr/bin/python3
"""The open-set measurement of issue 25 item 3, re-implemented in numpy (Debian python3-numpy) to compare novelty
distances over several random splits in seconds, where bench/novelty_open_set.sh runs `wish train` per class.
Leave-one-class-out on a labelled descriptor CSV (`wish train DIR --save-descriptors D.csv`): for each class and
each seed, a stratified 20 % test split of the known classes, z-scores fitted on the rest, the per-class k-NN
conformal figure of core/classify/novelty.hpp at quantile q calibrated on it; counted: the left-out class's members
flagged novel, the known test members flagged.
    bench/novelty_open_set_numpy.py D.csv [--combined] [--distance euclidean|whitened] [--min-shrinkage 0.5]
        [--k 3] [--quantile 0.99] [--seeds 5]
Distances: euclidean (model format 4), whitened (format 5: W = C^(-1/2), C the pooled within-class covariance,
Ledoit-Wolf shrunk towards mu I, shrinkage at least --min-shrinkage; 0 gives plain Ledoit-Wolf).
Features: log xi(1..L) (the default recipe), --combined adds the global descriptors (not logged), as
core/classify/feature_pipeline.cpp. The splits are numpy's, not wish's: the figures are the same method, other splits.
"""
import argparse
import csv

import numpy as np


def load(path, combined):
    rows = list(csv.DictReader(open(path)))
    xi = [k for k in rows[0] if k.startswith("xi_") and k != "xi_0"]
    gl = [k for k in rows[0] if k.startswith("g_")] if combined else []
    X = np.array([[np.log(max(float(r[k]), np.finfo(float).tiny)) for k in xi] + [float(r[k]) for k in gl] for r in rows])
    return X, np.array([r["label"] for r in rows])


def stratified_split(y, fraction, rng):
    train, test = [], []
    for c in np.unique(y):
        idx = np.where(y == c)[0]
        rng.shuffle(idx)
        n = int(round(fraction * len(idx)))
        test += list(idx[:n])
        train += list(idx[n:])
    return np.array(train), np.array(test)


def whitening(Z, y, min_shrinkage):
    """As core/classify/novelty.cpp within_class_whitening."""
    R = np.vstack([Z[y == c] - Z[y == c].mean(0) for c in np.unique(y)])
    n, p = R.shape
    S = R.T @ R / n
    mu = np.trace(S) / p
    d2 = np.sum((S - mu * np.eye(p)) ** 2)
    b2 = max(0.0, (np.sum(np.sum(R ** 2, axis=1) ** 2) - n * np.sum(S ** 2)) / n ** 2)
    s = max(min_shrinkage, min(b2, d2) / d2 if d2 > 0 else 1.0)
    ev, V = np.linalg.eigh((1 - s) * S + s * mu * np.eye(p))
    ev = np.maximum(ev, 1e-12 * ev.max())
    return V @ np.diag(ev ** -0.5) @ V.T


def knn_mean(D, k):
    return np.sort(D, axis=1)[:, :k].mean(axis=1)


def left_out_counts(X, y, left, args, seed):
    rng = np.random.default_rng(seed)
    known = y != left
    Xk, yk = X[known], y[known]
    tr, te = stratified_split(yk, 0.2, rng)
    mu, sd = Xk[tr].mean(0), Xk[tr].std(0)
    sd[sd == 0] = 1
    Z = (X - mu) / sd
    Zk = Z[known]
    W = whitening(Zk[tr], yk[tr], args.min_shrinkage) if args.distance == "whitened" else np.eye(X.shape[1])
    refs, thresholds = [], []
    for c in np.unique(yk[tr]):
        A = Zk[tr][yk[tr] == c] @ W
        k = max(1, min(args.k, len(A) - 1))
        D = np.linalg.norm(A[:, None] - A[None], axis=2)
        np.fill_diagonal(D, np.inf)
        refs.append((A, k))
        thresholds.append(np.quantile(knn_mean(D, k), args.quantile))

    def novel(P):  # above every class's threshold
        Pw = P @ W
        out = np.ones(len(P), bool)
        for (A, k), t in zip(refs, thresholds):
            out &= knn_mean(np.linalg.norm(Pw[:, None] - A[None], axis=2), k) > t
        return out

    return novel(Z[~known]).sum(), (~known).sum(), novel(Zk[te]).sum(), len(te)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--combined", action="store_true")
    ap.add_argument("--distance", choices=["euclidean", "whitened"], default="whitened")
    ap.add_argument("--min-shrinkage", type=float, default=0.5)
    ap.add_argument("--k", type=int, default=3)
    ap.add_argument("--quantile", type=float, default=0.99)
    ap.add_argument("--seeds", type=int, default=5)
    args = ap.parse_args()
    X, y = load(args.csv, args.combined)
    print("| left-out class | its members flagged novel | held-out known members flagged |")
    print("|---|---|---|")
    total = np.zeros(4, int)
    for left in np.unique(y):
        n = np.zeros(4, int)
        for seed in range(1, args.seeds + 1):
            n += left_out_counts(X, y, left, args, seed)
        total += n
        print(f"| {left} | {n[0]} of {n[1]} ({100 * n[0] / n[1]:.0f} %) | {n[2]} of {n[3]} |")
    print(f"| all | {total[0]} of {total[1]} ({100 * total[0] / total[1]:.1f} %) | {total[2]} of {total[3]} "
          f"({100 * total[2] / total[3]:.2f} %) |")


if __name__ == "__main__":
    main()
