#!/usr/bin/python3
"""The open-set measurement of issue 25 item 3, re-implemented in numpy (Debian python3-numpy) to compare novelty
distances over several random splits in seconds, where bench/novelty_open_set.sh runs `wish train` per class.
Leave-one-class-out on a labelled descriptor CSV (`wish train DIR --save-descriptors D.csv`): for each class and
each seed, a stratified 20 % test split of the known classes, z-scores fitted on the rest, the per-class k-NN
conformal figure of core/classify/novelty.hpp at quantile q calibrated on it; counted: the left-out class's members
flagged novel, the known test members flagged.
    bench/novelty_open_set_numpy.py D.csv [--combined] [--distance euclidean|whitened] [--min-shrinkage 0.5]
        [--k 3] [--quantile 0.99] [--seeds 5] [--calibration loo|cv] [--folds 10] [--whitening pooled|class]
        [--roc] [--ceiling]
Distances: euclidean (model format 4), whitened (format 5: W = C^(-1/2), C the pooled within-class covariance,
Ledoit-Wolf shrunk towards mu I, shrinkage at least --min-shrinkage; 0 gives plain Ledoit-Wolf).
Calibration: loo (the default, model formats 3-5) or cv (`wish train --novelty-folds N`, format 6: each training
sample scored against its class's members in the other folds, whitened by the other folds; numpy's folds).
--whitening class: one covariance per class (not in wish; a variant measured in docs/benchmarks.md).
--roc: also the share of the left-out class flagged at the threshold that flags exactly 1 % / 2 % of the held-out
known members (chosen on the answer: what the score could do with a perfect threshold, not a result).
--ceiling: a SUPERVISED detector that knows the left-out class (scikit-learn RBF SVM, left-out class against the rest,
5-fold CV, its own grid) at 1 % / 2 % of known members flagged: what the features allow at best.
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


def class_whitenings(Z, y, args):
    """Per class c, the W its distances are measured with."""
    cls = np.unique(y)
    if args.distance == "euclidean":
        return {c: np.eye(Z.shape[1]) for c in cls}
    if args.whitening == "class":
        out = {}
        for c in cls:
            A = Z[y == c]
            out[c] = whitening(A, np.zeros(len(A), int), args.min_shrinkage)
        return out
    W = whitening(Z, y, args.min_shrinkage)
    return {c: W for c in cls}


def stratified_folds(y, k, rng):
    """Classes dealt round-robin after a per-class shuffle, continuing where the previous class stopped (splits.cpp)."""
    f, nxt = np.zeros(len(y), int), 0
    for c in np.unique(y):
        idx = np.where(y == c)[0]
        rng.shuffle(idx)
        for i in idx:
            f[i] = nxt % k
            nxt += 1
    return f


def calibration_scores(Z, y, args, rng):
    """Per class, its calibration scores: leave-one-out, or cross-validated (novelty.cpp cross_validated_scores)."""
    cls = np.unique(y)
    n_c = {c: (y == c).sum() for c in cls}
    kc = {c: max(1, min(args.k, n_c[c] - 1)) for c in cls}
    out = {c: [] for c in cls}
    if args.calibration == "loo":
        Ws = class_whitenings(Z, y, args)
        for c in cls:
            A = Z[y == c] @ Ws[c]
            D = np.linalg.norm(A[:, None] - A[None], axis=2)
            np.fill_diagonal(D, np.inf)
            out[c] = knn_mean(D, kc[c])
        return out
    f = stratified_folds(y, min(args.folds, len(y)), rng)
    for i in range(f.max() + 1):
        Ws = class_whitenings(Z[f != i], y[f != i], args)
        for c in cls:
            A = Z[(f != i) & (y == c)] @ Ws[c]
            P = Z[(f == i) & (y == c)] @ Ws[c]
            if len(P) and n_c[c] >= 2:
                out[c] += list(knn_mean(np.linalg.norm(P[:, None] - A[None], axis=2), min(kc[c], len(A))))
    return {c: np.array(v) for c, v in out.items()}


def left_out_scores(X, y, left, args, seed):
    """The left-out class's and the held-out known members' figure: min over classes of score / threshold (novel
    above 1)."""
    rng = np.random.default_rng(seed)
    known = y != left
    Xk, yk = X[known], y[known]
    tr, te = stratified_split(yk, 0.2, rng)
    mu, sd = Xk[tr].mean(0), Xk[tr].std(0)
    sd[sd == 0] = 1
    Z = (X - mu) / sd
    Zk = Z[known]
    Ws = class_whitenings(Zk[tr], yk[tr], args)
    cal = calibration_scores(Zk[tr], yk[tr], args, rng)
    refs = []
    for c in np.unique(yk[tr]):
        A = Zk[tr][yk[tr] == c] @ Ws[c]
        refs.append((A, Ws[c], max(1, min(args.k, len(A) - 1)), np.quantile(cal[c], args.quantile)))

    def ratio(P):  # relative to each class's threshold; novel when above 1 for every class
        return np.min([knn_mean(np.linalg.norm((P @ W)[:, None] - A[None], axis=2), k) / t for A, W, k, t in refs],
                      axis=0)

    return ratio(Z[~known]), ratio(Zk[te])


def supervised_ceiling(X, y, left, fprs):
    from sklearn.model_selection import GridSearchCV, StratifiedKFold, cross_val_predict
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler
    from sklearn.svm import SVC
    t = (y == left).astype(int)
    clf = GridSearchCV(make_pipeline(StandardScaler(), SVC()),
                       {"svc__C": [1, 10, 100, 1000], "svc__gamma": [0.003, 0.01, 0.03, 0.1, 0.3]}, cv=5)
    s = cross_val_predict(clf, X, t, cv=StratifiedKFold(5, shuffle=True, random_state=1), method="decision_function")
    return [100 * (s[t == 1] > np.quantile(s[t == 0], 1 - f)).mean() for f in fprs]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--combined", action="store_true")
    ap.add_argument("--distance", choices=["euclidean", "whitened"], default="whitened")
    ap.add_argument("--whitening", choices=["pooled", "class"], default="pooled")
    ap.add_argument("--min-shrinkage", type=float, default=0.5)
    ap.add_argument("--k", type=int, default=3)
    ap.add_argument("--quantile", type=float, default=0.99)
    ap.add_argument("--calibration", choices=["loo", "cv"], default="loo")
    ap.add_argument("--folds", type=int, default=10)
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--roc", action="store_true")
    ap.add_argument("--ceiling", action="store_true")
    args = ap.parse_args()
    X, y = load(args.csv, args.combined)
    fprs = (0.01, 0.02)
    head = "| left-out class | its members flagged novel | held-out known members flagged |"
    if args.roc:
        head += " flagged at 1 % / 2 % known (threshold on the answer) |"
    if args.ceiling:
        head += " supervised ceiling at 1 % / 2 % |"
    print(head)
    print("|---" * (head.count("|") - 1) + "|")
    total = np.zeros(4, int)
    all_left, all_known, per_left = [], [], {}
    for left in np.unique(y):
        lo, kn = [], []
        for seed in range(1, args.seeds + 1):
            a, b = left_out_scores(X, y, left, args, seed)
            lo.append(a)
            kn.append(b)
        per_left[left] = (np.concatenate(lo), np.concatenate(kn))
        all_known.append(per_left[left][1])
    known_pooled = np.concatenate(all_known)
    cuts = [np.quantile(known_pooled, 1 - f) for f in fprs]
    for left, (a, b) in per_left.items():
        n = np.array([(a > 1).sum(), len(a), (b > 1).sum(), len(b)])
        total += n
        all_left.append(a)
        row = f"| {left} | {n[0]} of {n[1]} ({100 * n[0] / n[1]:.0f} %) | {n[2]} of {n[3]} |"
        if args.roc:
            row += " " + " / ".join(f"{100 * (a > c).mean():.0f} %" for c in cuts) + " |"
        if args.ceiling:
            row += " " + " / ".join(f"{v:.0f} %" for v in supervised_ceiling(X, y, left, fprs)) + " |"
        print(row)
    row = (f"| all | {total[0]} of {total[1]} ({100 * total[0] / total[1]:.1f} %) | {total[2]} of {total[3]} "
           f"({100 * total[2] / total[3]:.2f} %) |")
    if args.roc:
        pooled = np.concatenate(all_left)
        row += " " + " / ".join(f"{100 * (pooled > c).mean():.1f} %" for c in cuts) + " |"
    print(row)


if __name__ == "__main__":
    main()
