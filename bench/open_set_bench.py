#!/usr/bin/python3
"""Open-set scores and feature families, measured on labelled descriptor CSVs (issue 38 items 1 and 2).

    /usr/bin/python3 bench/open_set_bench.py D.csv [D.csv ...] [--families xi,global,combined,...]
        [--scores knn_min,knn_pred,gauss_pred,...] [--mode open|accuracy|both] [--folds 5] [--seed 1]
        [--max-per-class N] [--ceiling]

Input: descriptor CSVs with a label column, as `wish train DIR --save-descriptors D.csv` writes them
(xi_<l>, g_<name>; lb_<i> the Laplace-Beltrami spectrum; csh_<l>_<m>_<x|y|z> the SH coefficients in the canonical
frame, when the recipe computed them).

Open set (--mode open): every class of every set left out in turn. The samples are split into --folds stratified
folds (by the original labels, so the left-out class is split too); in fold f every score is fitted on the KNOWN
training rows only and scores the test rows (known and left-out). Over the folds each sample is scored once.
Reported per set, as the MEAN over the left-out classes (each class counts once, whatever its size): AUROC of the
score (left-out against known), the share of the left-out class flagged at the thresholds that flag exactly 2 % and
5 % of the known test rows (a ROC operating point, the same for every score and for the ceiling), and the
supervised ceiling: a binary RBF SVM trained WITH the left-out class (left-out against the rest), same features,
same folds, its decision value at the same operating points. The gap to the ceiling is what matters.
Every score is "larger = more novel". Scores:
  knn_min     today's figure (core/classify/novelty.cpp, model format 5): per class the mean whitened distance to
              its k = 3 nearest members divided by the class's 0.99 quantile of leave-one-out scores; the minimum
              over the classes
  knn_pred    the same ratio, for the class the SVM predicts only
  gauss_min   per class, the Mahalanobis distance to the class mean, covariance = the class's own shrunk towards
              the pooled within-class one (Ledoit-Wolf towards mu I, at least 0.5); in units of the class's own
              cross-validated distances (their 0.95 quantile); the minimum over the classes
  gauss_pred  the same, for the class the SVM predicts only
  maxprob     1 - the SVM's largest Platt probability
  margin      minus the SVM's decision-value margin of the winner over the runner-up
  knn_gauss   the mean of knn_min and gauss_pred (both in units of a class's spread)
  combo       the conformal p-values of gauss_pred and maxprob against known rows held out inside the training
              rows (5 inner folds), combined by the smaller of the two (score: -log of it)
Accuracy (--mode accuracy): nested CV (outer 5 folds, inner grid C 1e-1..1e5 x gamma/d 1e-3..1e1 over 3 folds),
per feature family. Families (features before the z-score): xi (log xi 1..L), global, combined (xi + global),
lb (log of the area-normalised Laplace-Beltrami eigenvalues), lb_global, csh (canonical SH coefficients divided
by sqrt(area)), csh_global, xi_lb_global, all.
"""
import argparse
import csv
import sys
import warnings

import numpy as np
from sklearn.metrics import roc_auc_score
from sklearn.model_selection import GridSearchCV, StratifiedKFold
from sklearn.preprocessing import StandardScaler
from sklearn.svm import SVC

warnings.filterwarnings("ignore")
TINY = np.finfo(float).tiny
C_GRID = [0.1, 1, 10, 100, 1000, 1e4, 1e5]
G_GRID = [1e-3, 1e-2, 0.1, 1, 10]  # times 1/d


def load(path, max_per_class=0):
    rows = list(csv.DictReader(open(path)))
    if max_per_class:
        by = {}
        for r in rows:
            by.setdefault(r["label"], []).append(r)
        rows = []
        for lab, rs in sorted(by.items()):
            rs = sorted(rs, key=lambda r: r["file"])
            if len(rs) > max_per_class:
                idx = np.linspace(0, len(rs) - 1, max_per_class).round().astype(int)
                rs = [rs[i] for i in idx]
            rows += rs
    return rows


def block(rows, prefix, transform=None, skip=()):
    keys = [k for k in rows[0] if k.startswith(prefix) and k not in skip]
    if not keys:
        return None
    X = np.array([[float(r[k]) for k in keys] for r in rows])
    return transform(X, rows) if transform else X


def log_pos(X, rows=None):
    return np.log(np.maximum(X, TINY))


def csh_scaled(X, rows):
    area = np.array([float(r["g_area"]) for r in rows])
    return X / np.sqrt(area)[:, None]


def family(rows, name):
    parts = {
        "xi": lambda: block(rows, "xi_", log_pos, skip=("xi_0",)),
        "global": lambda: block(rows, "g_"),
        "lb": lambda: block(rows, "lb_", log_pos),
        "csh": lambda: block(rows, "csh_", csh_scaled),
    }
    spec = {"combined": "xi+global", "lb_global": "lb+global", "csh_global": "csh+global",
            "xi_lb_global": "xi+lb+global", "all": "xi+lb+csh+global"}.get(name, name)
    blocks = [parts[p]() for p in spec.split("+")]
    if any(b is None for b in blocks):
        return None
    return np.hstack(blocks)


# ---- scores ----
def shrunk_whitening(R, min_shrinkage=0.5):
    """C^(-1/2) of the covariance of the residual rows R, Ledoit-Wolf towards mu I, shrinkage >= min (novelty.cpp)."""
    n, p = R.shape
    S = R.T @ R / n
    mu = np.trace(S) / p
    if mu <= 0:
        return np.eye(p), np.eye(p)
    d2 = np.sum((S - mu * np.eye(p)) ** 2)
    b2 = max(0.0, (np.sum(np.sum(R ** 2, axis=1) ** 2) - n * np.sum(S ** 2)) / n ** 2)
    s = max(min_shrinkage, min(b2, d2) / d2 if d2 > 0 else 1.0)
    C = (1 - s) * S + s * mu * np.eye(p)
    ev, V = np.linalg.eigh(C)
    ev = np.maximum(ev, 1e-12 * ev.max())
    return V @ np.diag(ev ** -0.5) @ V.T, C


def residuals(Z, y):
    return np.vstack([Z[y == c] - Z[y == c].mean(0) for c in np.unique(y)])


def knn_mean(D, k):
    return np.sort(D, axis=1)[:, :k].mean(axis=1)


class KnnScore:
    def __init__(self, Z, y, k=3, q=0.99, min_shrinkage=0.5):
        self.W, _ = shrunk_whitening(residuals(Z, y), min_shrinkage)
        self.cls = np.unique(y)
        self.refs = []
        for c in self.cls:
            A = Z[y == c] @ self.W
            kc = max(1, min(k, len(A) - 1))
            D = np.linalg.norm(A[:, None] - A[None], axis=2)
            np.fill_diagonal(D, np.inf)
            t = np.quantile(knn_mean(D, kc), q) if len(A) > 1 else np.nan
            self.refs.append((A, kc, t))
        ts = [t for _, _, t in self.refs if np.isfinite(t)]
        self.refs = [(A, kc, t if np.isfinite(t) else max(ts)) for A, kc, t in self.refs]

    def ratios(self, P):
        P = P @ self.W
        return np.array([knn_mean(np.linalg.norm(P[:, None] - A[None], axis=2), kc) / t for A, kc, t in self.refs]).T


class GaussScore:
    """Per class: Mahalanobis distance to the class mean, the class's covariance shrunk towards the pooled one."""

    def __init__(self, Z, y, q=0.95, folds=5, seed=0, alpha=None):
        self.cls = np.unique(y)
        self.alpha = alpha
        self.models = self._fit(Z, y)
        # Cross-validated calibration: each training row scored by a model fitted without its fold.
        cal = {c: [] for c in self.cls}
        nmin = min((y == c).sum() for c in self.cls)
        f = min(folds, nmin) if nmin >= 2 else 0
        if f >= 2:
            for tr, te in StratifiedKFold(f, shuffle=True, random_state=seed).split(Z, y):
                m = self._fit(Z[tr], y[tr])
                d = self._dist(m, Z[te])
                for i, c in enumerate(self.cls):
                    cal[c] += list(d[y[te] == c, i])
        self.scale = np.array([np.quantile(cal[c], q) if len(cal[c]) else 1.0 for c in self.cls])
        self.cal = cal

    def _fit(self, Z, y):
        R = residuals(Z, y)
        p = Z.shape[1]
        _, Cp = shrunk_whitening(R)
        out = []
        for c in self.cls:
            A = Z[y == c]
            n = len(A)
            m = A.mean(0)
            Sc = np.cov(A.T, bias=True) if n > 1 else np.zeros((p, p))
            Sc = np.atleast_2d(Sc)
            a = self.alpha if self.alpha is not None else max(0.5, p / (n + p))
            C = (1 - a) * Sc + a * Cp
            ev, V = np.linalg.eigh(C)
            ev = np.maximum(ev, 1e-12 * ev.max())
            out.append((m, V @ np.diag(ev ** -0.5) @ V.T))
        return out

    def _dist(self, models, P):
        return np.array([np.linalg.norm((P - m) @ W, axis=1) for m, W in models]).T

    def ratios(self, P):
        return self._dist(self.models, P) / self.scale


class KnnScale:
    """k-NN distance (whitened by the pooled within-class covariance, as KnnScore) to each class, in units of that
    class's OWN typical k-NN distance: the median of its members' leave-one-out k-NN distances (not a tail
    quantile, which a few stragglers move)."""

    def __init__(self, Z, y, k=3):
        self.W, _ = shrunk_whitening(residuals(Z, y))
        self.refs = []
        for c in np.unique(y):
            A = Z[y == c] @ self.W
            kc = max(1, min(k, len(A) - 1))
            D = np.linalg.norm(A[:, None] - A[None], axis=2)
            np.fill_diagonal(D, np.inf)
            t = np.median(knn_mean(D, kc)) if len(A) > 1 else np.nan
            self.refs.append((A, kc, t))
        ts = [t for _, _, t in self.refs if np.isfinite(t) and t > 0]
        self.refs = [(A, kc, t if np.isfinite(t) and t > 0 else max(ts)) for A, kc, t in self.refs]

    def ratios(self, P):
        P = P @ self.W
        return np.array([knn_mean(np.linalg.norm(P[:, None] - A[None], axis=2), kc) / t for A, kc, t in self.refs]).T


class KnnAll:
    """k-NN distance to the whole known training set, whitened by the pooled within-class covariance (no classes)."""

    def __init__(self, Z, y, k=1):
        self.W, _ = shrunk_whitening(residuals(Z, y))
        self.A = Z @ self.W
        self.k = k

    def score(self, P):
        return knn_mean(np.linalg.norm((P @ self.W)[:, None] - self.A[None], axis=2), self.k)


class LwScore:
    """Per class: Mahalanobis distance to the class mean with the class's OWN covariance, Ledoit-Wolf shrunk
    (sklearn.covariance.LedoitWolf, towards mu I); pooled: one pooled within-class covariance (Lee et al. 2018)."""

    def __init__(self, Z, y, pooled=False):
        from sklearn.covariance import LedoitWolf
        self.models = []
        R = residuals(Z, y)
        Wp = None
        if pooled:
            C = LedoitWolf(assume_centered=True).fit(R).covariance_
            ev, V = np.linalg.eigh(C)
            Wp = V @ np.diag(np.maximum(ev, 1e-12 * ev.max()) ** -0.5) @ V.T
        for c in np.unique(y):
            A = Z[y == c]
            if pooled or len(A) < 3:
                W = Wp if Wp is not None else shrunk_whitening(R)[0]
            else:
                C = LedoitWolf().fit(A).covariance_
                ev, V = np.linalg.eigh(C)
                W = V @ np.diag(np.maximum(ev, 1e-12 * ev.max()) ** -0.5) @ V.T
            self.models.append((A.mean(0), W))

    def dist(self, P):
        return np.array([np.linalg.norm((P - m) @ W, axis=1) for m, W in self.models]).T


class FeatMax:
    """Per class, the largest feature-wise deviation from the class median in units of the class's spread of that
    feature (its MAD * 1.4826, floored at a quarter of the pooled within-class one); the minimum over the classes."""

    def __init__(self, Z, y):
        R = residuals(Z, y)
        pooled = 1.4826 * np.median(np.abs(R - np.median(R, 0)), 0) + 1e-9
        self.models = []
        for c in np.unique(y):
            A = Z[y == c]
            med = np.median(A, 0)
            mad = 1.4826 * np.median(np.abs(A - med), 0)
            self.models.append((med, np.maximum(mad, 0.25 * pooled)))

    def dist(self, P):
        return np.array([np.max(np.abs(P - m) / s, axis=1) for m, s in self.models]).T


def svm_free_scores(Ztr, ytr, P):
    """The scores that need no SVM (cheap enough to re-fit inside the training rows for calibration)."""
    out = {}
    kr = KnnScore(Ztr, ytr, q=0.99).ratios(P)
    out["knn_min"] = kr.min(1)
    ks = KnnScale(Ztr, ytr).ratios(P)
    out["knnscale_min"] = ks.min(1)
    out["knn1_all"] = KnnAll(Ztr, ytr, k=1).score(P)
    out["knn3_all"] = KnnAll(Ztr, ytr, k=3).score(P)
    out["lw_min"] = LwScore(Ztr, ytr).dist(P).min(1)
    out["pooled_min"] = LwScore(Ztr, ytr, pooled=True).dist(P).min(1)
    out["knnlw_min"] = KnnScore(Ztr, ytr, q=0.99, min_shrinkage=0.0).ratios(P).min(1)
    out["featmax_min"] = FeatMax(Ztr, ytr).dist(P).min(1)
    from sklearn.ensemble import IsolationForest
    out["iforest"] = -IsolationForest(n_estimators=200, random_state=0).fit(Ztr).score_samples(P)
    return out


def fit_svm(Z, y, seed=0, probability=True, inner=3):
    d = Z.shape[1]
    nmin = min(np.bincount(np.unique(y, return_inverse=True)[1]))
    cv = StratifiedKFold(max(2, min(inner, nmin)), shuffle=True, random_state=seed)
    g = GridSearchCV(SVC(kernel="rbf"), {"C": C_GRID, "gamma": [x / d for x in G_GRID]}, cv=cv, n_jobs=1)
    g.fit(Z, y)
    best = g.best_params_
    return SVC(kernel="rbf", probability=probability, random_state=seed, **best).fit(Z, y)


def svm_outputs(svm, P):
    prob = svm.predict_proba(P)
    dv = svm.decision_function(P)
    if dv.ndim == 1:
        margin = np.abs(dv)
    else:
        s = np.sort(dv, axis=1)
        margin = s[:, -1] - s[:, -2]
    pred = svm.predict(P)
    return prob, margin, pred


def conformal_p(cal, s):
    cal = np.sort(cal)
    return (1 + len(cal) - np.searchsorted(cal, s, side="left")) / (len(cal) + 1)


OLD_SCORES = {"knn_min", "knn_pred", "gauss_min", "gauss_pred", "maxprob", "margin", "knn_gauss", "combo"}
SVM_FREE = {"knn_min", "knnscale_min", "knn1_all", "knn3_all", "lw_min", "pooled_min", "knnlw_min", "featmax_min", "iforest"}
PRED = {"knnscale_pred", "lw_pred"}


def parse_score(name):
    """NAME[@family][~robust] -> (NAME, family or None, scaler). rank:A+B+... combines SVM-free scores."""
    scaler = "standard"
    if name.endswith("~robust"):
        name, scaler = name[: -len("~robust")], "robust"
    fam = None
    if "@" in name and not name.startswith("rank:"):
        name, fam = name.split("@")
    return name, fam, scaler


def transformed(rows, X_main, fam, scaler, fit_idx, apply_idx, cache):
    key = (fam, scaler)
    if key not in cache:
        cache[key] = X_main if fam is None else family(rows, fam)
    X = cache[key]
    from sklearn.preprocessing import RobustScaler
    sc = (RobustScaler() if scaler == "robust" else StandardScaler()).fit(X[fit_idx])
    return sc.transform(X[fit_idx]), sc.transform(X[apply_idx])


def extra_fold_scores(rows, X_main, y, ktr, te, names, pi, seed, xcache, inner=5):
    """The new scores (issue 38, second pass) of the test rows te, fitted on the known training rows ktr only.
    pi: the main family's SVM prediction (class index into np.unique(y[ktr])) for every test row.
    rank:A+B+...: each component's conformal rank against its own scores of known training rows held out in `inner`
    stratified folds inside ktr (fitted on the other inner folds), averaged; larger = more novel."""
    out = {}
    free_cache, cal_cache = {}, {}
    ytr = y[ktr]
    rr = np.arange(len(te))

    def free(fam, scaler):
        if (fam, scaler) not in free_cache:
            Ztr, P = transformed(rows, X_main, fam, scaler, ktr, te, xcache)
            free_cache[(fam, scaler)] = svm_free_scores(Ztr, ytr, P)
        return free_cache[(fam, scaler)]

    def cal(fam, scaler):
        if (fam, scaler) not in cal_cache:
            acc = {}
            for itr, ite in StratifiedKFold(inner, shuffle=True, random_state=seed).split(ktr, ytr):
                Ztr, P = transformed(rows, X_main, fam, scaler, ktr[itr], ktr[ite], xcache)
                for k, v in svm_free_scores(Ztr, ytr[itr], P).items():
                    acc.setdefault(k, []).extend(v)
            cal_cache[(fam, scaler)] = {k: np.array(v) for k, v in acc.items()}
        return cal_cache[(fam, scaler)]

    for n in names:
        if n.startswith("rank:"):
            ranks = []
            for comp in n[len("rank:"):].split("+"):
                b, fam, scaler = parse_score(comp)
                ranks.append(1 - conformal_p(cal(fam, scaler)[b], free(fam, scaler)[b]))
            out[n] = np.mean(ranks, axis=0)
            continue
        b, fam, scaler = parse_score(n)
        if b in SVM_FREE and (fam is not None or scaler != "standard" or b not in OLD_SCORES):
            out[n] = free(fam, scaler)[b]
        elif b in PRED or (b in ("knn_pred", "gauss_pred") and (fam is not None or scaler != "standard")):
            Ztr, P = transformed(rows, X_main, fam, scaler, ktr, te, xcache)
            if b == "knnscale_pred":
                out[n] = KnnScale(Ztr, ytr).ratios(P)[rr, pi]
            elif b == "lw_pred":
                out[n] = LwScore(Ztr, ytr).dist(P)[rr, pi]
            elif b == "knn_pred":
                out[n] = KnnScore(Ztr, ytr).ratios(P)[rr, pi]
            else:
                out[n] = GaussScore(Ztr, ytr, seed=seed).ratios(P)[rr, pi]
    return out


def fold_scores(Ztr, ytr, P, names, seed, need_pred=False):
    """Every requested score of the rows P, from the known training rows (Ztr, ytr)."""
    out = {}
    if not names and not need_pred:
        return out
    svm = fit_svm(Ztr, ytr, seed)
    prob, margin, pred = svm_outputs(svm, P)
    cls = list(svm.classes_)
    pi = np.array([cls.index(c) for c in pred])
    rows = np.arange(len(P))
    need_knn = any(n.startswith("knn") for n in names)
    need_gauss = any(n.startswith("gauss") or n in ("combo", "knn_gauss") for n in names)
    if need_knn:
        kr = KnnScore(Ztr, ytr, q=0.99).ratios(P)
        out["knn_min"] = kr.min(1)
        out["knn_pred"] = kr[rows, pi]
        # The same ratios against each class's 0.95 quantile: > 1 is what a model at quantile 0.95 flags.
        kr95 = KnnScore(Ztr, ytr, q=0.95).ratios(P)
        out["flag95_min"] = (kr95.min(1) > 1).astype(float)
        out["flag95_pred"] = (kr95[rows, pi] > 1).astype(float)
    if need_gauss:
        gs = GaussScore(Ztr, ytr, seed=seed)
        gr = gs.ratios(P)
        out["gauss_min"] = gr.min(1)
        out["gauss_pred"] = gr[rows, pi]
    if need_knn and need_gauss:  # both in units of the class's spread: their mean, a simple combination
        out["knn_gauss"] = 0.5 * (out["knn_min"] + out["gauss_pred"])
    out["maxprob"] = 1 - prob.max(1)
    out["margin"] = -margin
    if "combo" in names:
        # calibration rows: known training rows scored out of fold
        cal_g, cal_p = [], []
        for tr, te in StratifiedKFold(5, shuffle=True, random_state=seed).split(Ztr, ytr):
            s2 = fit_svm(Ztr[tr], ytr[tr], seed)
            pr2, _, pd2 = svm_outputs(s2, Ztr[te])
            g2 = GaussScore(Ztr[tr], ytr[tr], seed=seed)
            c2 = list(g2.cls)
            gi = np.array([c2.index(c) for c in pd2])
            cal_g += list(g2.ratios(Ztr[te])[np.arange(len(te)), gi])
            cal_p += list(1 - pr2.max(1))
        pg = conformal_p(np.array(cal_g), out["gauss_pred"])
        pp = conformal_p(np.array(cal_p), out["maxprob"])
        out["combo"] = -np.log(np.minimum(pg, pp))
    res = {n: out[n] for n in names + [k for k in out if k.startswith("flag95")]}
    res["_pred_index"] = pi
    return res


def detection(known, unseen, fpr):
    t = np.quantile(known, 1 - fpr)
    return 100 * (unseen > t).mean()


def open_set(X, y, names, args, rows=None):
    labels = np.unique(y)
    old = [n for n in names if n in OLD_SCORES]
    extra = [n for n in names if n not in OLD_SCORES]
    xcache = {}
    res = {n: [] for n in names + ["ceiling"]}
    per_class = []
    for left in labels:
        scores = {n: np.zeros(len(y)) for n in names + ["ceiling", "flag95_min", "flag95_pred"]}
        tested = np.zeros(len(y), bool)
        for f, (tr, te) in enumerate(StratifiedKFold(args.folds, shuffle=True, random_state=args.seed).split(X, y)):
            ktr = tr[y[tr] != left]
            sc = StandardScaler().fit(X[ktr])
            Ztr, P = sc.transform(X[ktr]), sc.transform(X[te])
            fs = fold_scores(Ztr, y[ktr], P, old, args.seed + f, need_pred=bool(extra))
            pi = fs.pop("_pred_index", None)
            if extra:
                fs.update(extra_fold_scores(rows, X, y, ktr, te, extra, pi, args.seed + f, xcache))
            for n in fs:
                scores[n][te] = fs[n]
            if args.ceiling:
                Xc = X if not args.ceiling_family else family(rows, args.ceiling_family)
                sc2 = StandardScaler().fit(Xc[tr])
                t = (y[tr] == left).astype(int)
                svm = fit_svm(sc2.transform(Xc[tr]), t, args.seed + f, probability=False)
                scores["ceiling"][te] = svm.decision_function(sc2.transform(Xc[te])) * (1 if svm.classes_[1] == 1 else -1)
            tested[te] = True
        u = y == left
        row = [left, int(u.sum())]
        for n in names + (["ceiling"] if args.ceiling else []):
            s = scores[n]
            a = 100 * roc_auc_score(u, s)
            d2, d5 = detection(s[~u], s[u], 0.02), detection(s[~u], s[u], 0.05)
            res[n].append((a, d2, d5))
            row.append((a, d2, d5))
        if "knn_min" in names:  # what a model calibrated at quantile 0.95 flags: unseen / known (%)
            for n in ("flag95_min", "flag95_pred"):
                res.setdefault(n, []).append((100 * scores[n][u].mean(), 100 * scores[n][~u].mean(), 0))
        per_class.append(row)
    return res, per_class


def nested_accuracy(X, y, args):
    accs = []
    for tr, te in StratifiedKFold(args.folds, shuffle=True, random_state=args.seed).split(X, y):
        sc = StandardScaler().fit(X[tr])
        svm = fit_svm(sc.transform(X[tr]), y[tr], args.seed, probability=False)
        accs.append(100 * (svm.predict(sc.transform(X[te])) == y[te]).mean())
    return np.mean(accs), np.std(accs)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--families", default="xi,global,combined")
    ap.add_argument("--scores", default="knn_min,knn_pred,gauss_min,gauss_pred,maxprob,margin,combo")
    ap.add_argument("--mode", choices=["open", "accuracy", "both"], default="open")
    ap.add_argument("--folds", type=int, default=5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-per-class", type=int, default=0)
    ap.add_argument("--ceiling", action="store_true")
    ap.add_argument("--ceiling-family", default="", help="the ceiling's features (default: the row's family); a "
                    "score on other features (@fam) is fairly compared with the ceiling on the union of both")
    ap.add_argument("--per-class", action="store_true", help="also print every left-out class's row")
    args = ap.parse_args()
    names = args.scores.split(",")
    fams = args.families.split(",")
    if args.mode in ("accuracy", "both"):
        print("| set (n, classes) | " + " | ".join(fams) + " |")
        print("|---" * (len(fams) + 1) + "|")
        for path in args.csv:
            rows = load(path, args.max_per_class)
            y = np.array([r["label"] for r in rows])
            cells = []
            for fam in fams:
                X = family(rows, fam)
                cells.append("-" if X is None else "%.1f ± %.1f" % nested_accuracy(X, y, args))
            print(f"| {path} ({len(y)}, {len(np.unique(y))}) | " + " | ".join(cells) + " |", flush=True)
    if args.mode in ("open", "both"):
        cols = names + (["ceiling"] if args.ceiling else [])
        print("\nopen set: mean over left-out classes of AUROC / detected at 2 % / 5 % known flagged")
        print("| set, family | " + " | ".join(cols) + (" | gap at 5 % (best score) |" if args.ceiling else " |"))
        print("|---" * (len(cols) + 1 + (1 if args.ceiling else 0)) + "|")
        for path in args.csv:
            rows = load(path, args.max_per_class)
            y = np.array([r["label"] for r in rows])
            for fam in fams:
                X = family(rows, fam)
                if X is None:
                    continue
                res, per_class = open_set(X, y, names, args, rows)
                mean = {n: np.mean(v, axis=0) for n, v in res.items() if v}
                cells = ["%.1f / %.0f / %.0f" % tuple(mean[n]) for n in cols]
                line = f"| {path.split('/')[-1]} {fam} | " + " | ".join(cells) + " |"
                if args.ceiling:
                    best = max(names, key=lambda n: mean[n][2])
                    line += f" {mean['ceiling'][2] - mean[best][2]:.1f} ({best}) |"
                if "flag95_min" in mean:
                    line += " q 0.95 flags (unseen / known): min %.0f / %.1f, pred %.0f / %.1f |" % (
                        mean["flag95_min"][0], mean["flag95_min"][1], mean["flag95_pred"][0], mean["flag95_pred"][1])
                print(line, flush=True)
                if args.per_class:
                    for row in per_class:
                        print(f"|   {row[0]} ({row[1]}) | " + " | ".join("%.1f / %.0f / %.0f" % c for c in row[2:]) + " |")


if __name__ == "__main__":
    main()
