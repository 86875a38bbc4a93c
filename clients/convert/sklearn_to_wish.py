#!/usr/bin/python3
"""Convert a scikit-learn ``Pipeline(StandardScaler, SVC(kernel="rbf"))`` into a WISH model file.

People train in notebooks on ``wish describe --csv`` features; the service loads one sealed JSON model file
(core/classify/model_file.cpp, format ``wish-classifier`` version 1). This module:

* :func:`features_from_describe_csv` — the feature pipeline of the model file (docs/design/classification.md), in numpy,
  exactly as the service replays it: ξ(l) for l in [l_min, l_max], optional scale normalisation (ξ(l)/ξ(1)),
  optional natural log (floored at the smallest normal double). Train the Pipeline on *these* columns.
* :func:`pipeline_to_model` — the fitted Pipeline + the feature spec + the descriptor settings → model document,
  sealed as the C++ loader checks it (wish_model_json.py).
* :func:`predict_with_model` — libsvm's prediction (one-vs-one votes, pairwise Platt probabilities coupled as in
  libsvm's ``multiclass_probability``) from the model document alone, in numpy: what the service will answer.

Command line (``/usr/bin/python3 clients/convert/sklearn_to_wish.py --help``):

    train    DESCRIBE.csv --labels LABELS.csv --out model.json [--C 10 --gamma 0.01 | grid search]
    convert  PIPELINE.pickle --out model.json --lmax 5 [--log] [--scale xi1]
    check    model.json DESCRIBE.csv [--pipeline PIPELINE.pickle]     (predictions of the model file)

The descriptor settings recorded in the model must be those the CSV was computed with: pass ``--lmax`` (and the
other settings if you changed them), or ``--descriptor-from`` an existing model file (e.g. data/models/default.json)
to copy its settings. Only the invariants feature family is supported (the CSV has no global descriptors).
"""

from __future__ import annotations

import argparse
import copy
import csv
import datetime as _dt
import hashlib
import json
import math
import pickle
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))  # clients/python: the client library
from wish_client import describe_csv  # noqa: E402
from wish_model_json import dumps, seal  # noqa: E402

FORMAT_NAME, FORMAT_VERSION = "wish-classifier", 2
# Versions this module reads. 3 to 6 only add the optional novelty block (core/classify/novelty.hpp: 3 one
# reference set, 4 per class, 5 per class in a whitened space, 6 with cross-validated calibration scores), which a
# converted model does not carry, so reading them for their recipe is safe; what this module writes stays version 2
# (no novelty block: the model answers "novel": null).
READABLE_VERSIONS = (1, 2, 3, 4, 5, 6)

#: The descriptor settings come from a model file written by `wish train` (by default the repository's bundled
#: model), never from a copy of the C++ defaults that could drift: the model file lists every setting.
BUNDLED_MODEL = Path(__file__).resolve().parents[2] / "data" / "models" / "default.json"


def default_descriptor() -> dict[str, Any]:
    """The descriptor block of the bundled default model (``wish train``'s defaults; Lmax is set from the CSV)."""
    if not BUNDLED_MODEL.is_file():
        raise ValueError(f"no bundled model at {BUNDLED_MODEL}: pass --descriptor-from MODEL.json")
    return descriptor_of(read_model(BUNDLED_MODEL, check_seal=False))


def descriptor_of(doc: dict[str, Any]) -> dict[str, Any]:
    """The map and fit settings (``{"map", "sh", "off_recipe", "recipe_version"}``) of a model document read by
    :func:`read_model`. The recipe version goes with them: it says which fields ``map`` and ``sh`` hold
    (core/classify/descriptor_recipe_codec.hpp), and the C++ loader refuses keys its version does not have."""
    recipe = doc["payload"]["recipe"]
    return copy.deepcopy({"map": recipe["map"], "sh": recipe["sh"], "off_recipe": recipe["off_recipe"],
                          "recipe_version": recipe["recipe_version"]})


_DBL_MIN = float(np.finfo(float).tiny)  # std::numeric_limits<double>::min(), the log floor in feature_pipeline.cpp


# ---- features -------------------------------------------------------------------------------------------------------

def read_describe_csv(path: str | Path) -> tuple[list[str], np.ndarray, list[str] | None]:
    """``(files, xi, labels)`` from ``wish describe --csv`` (xi: n × (Lmax+1); labels from a label/class column),
    read by the client library's one reader of that CSV (clients/python/wish_client/describe_csv.py)."""
    table = describe_csv.read_describe_csv(path)
    return table.files, np.asarray(table.xi, dtype=float), table.labels


def apply_feature_spec(xi: np.ndarray, spec: dict[str, Any]) -> np.ndarray:
    """The service's feature pipeline (core/classify/feature_pipeline.cpp) on rows of ξ(0..Lmax)."""
    xi = np.atleast_2d(np.asarray(xi, dtype=float))
    l_min, l_max = int(spec["l_min"]), int(spec["l_max"])
    if xi.shape[1] < l_max + 1:
        raise ValueError(f"the features use xi({l_max}) but the descriptors stop at xi({xi.shape[1] - 1})")
    divisor = np.ones((xi.shape[0], 1))
    if spec.get("scale", "none") == "xi1":
        divisor = xi[:, [1]]
    elif spec.get("scale", "none") != "none":
        raise ValueError(f"scale {spec['scale']!r} is not supported by the converter (none, xi1)")
    x = xi[:, l_min:l_max + 1] / divisor
    if spec.get("log", False):
        x = np.log(np.maximum(x, _DBL_MIN))
    if not np.isfinite(x).all():
        raise ValueError("the feature matrix contains NaN or infinity")
    return x


def feature_spec(l_max: int, l_min: int = 1, scale: str = "none", log: bool = False) -> dict[str, Any]:
    """The model file's ``features`` block for the invariants family."""
    return {"family": "invariants", "l_min": l_min, "l_max": l_max, "scale": scale, "log": bool(log),
            "global_scale_free": False, "names": [f"xi_{l}" for l in range(l_min, l_max + 1)]}


def features_from_describe_csv(path: str | Path, l_max: int | None = None, l_min: int = 1, scale: str = "none",
                               log: bool = False) -> tuple[list[str], np.ndarray, dict[str, Any]]:
    """``(files, X, spec)``: the feature matrix to train the Pipeline on, and the spec to record in the model."""
    files, xi, _ = read_describe_csv(path)
    spec = feature_spec(l_max if l_max is not None else xi.shape[1] - 1, l_min, scale, log)
    return files, apply_feature_spec(xi, spec), spec


# ---- conversion -----------------------------------------------------------------------------------------------------

def _unpack_pipeline(pipeline: Any) -> tuple[Any, Any]:
    from sklearn.pipeline import Pipeline
    from sklearn.preprocessing import StandardScaler
    from sklearn.svm import SVC

    if not isinstance(pipeline, Pipeline) or len(pipeline.steps) != 2:
        raise TypeError("expected a fitted Pipeline of exactly two steps: StandardScaler, SVC(kernel='rbf')")
    scaler, svc = pipeline.steps[0][1], pipeline.steps[1][1]
    if not isinstance(scaler, StandardScaler) or not isinstance(svc, SVC):
        raise TypeError(f"expected StandardScaler then SVC, got {type(scaler).__name__} then {type(svc).__name__}")
    if svc.kernel != "rbf":
        raise ValueError(f"only the RBF kernel is supported, got kernel={svc.kernel!r}")
    if not hasattr(svc, "support_vectors_"):
        raise ValueError("the Pipeline is not fitted")
    if not svc.probability:
        raise ValueError("the service reports probabilities: train the SVC with probability=True")
    if getattr(svc, "class_weight_", None) is not None and not np.allclose(svc.class_weight_, 1.0):
        pass  # class weights only shape training; the fitted model is the same kind of object
    return scaler, svc


def pipeline_to_model(pipeline: Any, spec: dict[str, Any], *, descriptor: dict[str, Any] | None = None,
                      lmax: int | None = None, name: str = "sklearn-svm", version: str = "1",
                      training: dict[str, Any] | None = None) -> dict[str, Any]:
    """The sealed model document for a fitted ``Pipeline(StandardScaler, SVC(kernel="rbf", probability=True))``.

    Args:
        pipeline: fitted on the columns of :func:`apply_feature_spec` (``spec``), labels = class-name strings.
        spec: the ``features`` block (:func:`feature_spec`).
        descriptor: map and fit settings (``{"map", "sh"}`` and optionally ``"off_recipe"`` and
            ``"recipe_version"`` (1 when absent), as
            :func:`descriptor_of` gives them); default :func:`default_descriptor`.
        lmax: overrides ``descriptor.sh.lmax`` (default: the spec's l_max).
        training: fields of the ``training`` block to set (samples, best_c, test_accuracy, notes, ...).
    """
    scaler, svc = _unpack_pipeline(pipeline)
    n_features = len(spec["names"])
    if scaler.mean_.shape[0] != n_features or svc.support_vectors_.shape[1] != n_features:
        raise ValueError(f"the Pipeline has {svc.support_vectors_.shape[1]} features, the spec makes {n_features}")
    desc = copy.deepcopy(descriptor or default_descriptor())
    desc["sh"]["lmax"] = int(lmax if lmax is not None else max(spec["l_max"], 0))
    if spec["l_max"] > desc["sh"]["lmax"]:
        raise ValueError(f"features use xi({spec['l_max']}) but the descriptor's lmax is {desc['sh']['lmax']}")
    classes = [str(c) for c in svc.classes_]
    if sorted(classes) != classes:
        raise ValueError("class labels must be strings that sort like scikit-learn's classes_")
    k = len(classes)
    # libsvm's own sign conventions: scikit-learn keeps them in _dual_coef_/_intercept_ (intercept = -rho); the
    # public dual_coef_/intercept_ are flipped for two classes.
    sv_coef = np.asarray(svc._dual_coef_, dtype=float)
    rho = -np.asarray(svc._intercept_, dtype=float)
    scale = np.asarray(scaler.scale_ if scaler.scale_ is not None else np.ones(n_features), dtype=float)
    mean = np.asarray(scaler.mean_ if scaler.mean_ is not None else np.zeros(n_features), dtype=float)
    now = _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0).isoformat().replace("+00:00", "Z")
    train = {"dataset_sha256": "", "trained_at": now, "samples": int(svc.shape_fit_[0]), "best_c": float(svc.C),
             "best_gamma": float(svc._gamma), "grid_score": 0.0, "test_accuracy": 0.0, "nested_cv_mean": 0.0,
             "nested_cv_std": 0.0, "notes": "converted from scikit-learn by clients/convert/sklearn_to_wish.py"}
    train.update(training or {})
    recipe_version = int(desc.get("recipe_version", 1))
    if recipe_version >= 4:  # features.spectrum_count exists from recipe version 4 (descriptor_recipe_codec.hpp)
        spec = {**spec, "spectrum_count": int(spec.get("spectrum_count", 0))}
    payload = {
        "name": name, "version": str(version), "classes": classes,
        # The descriptor recipe (format 2): map + fit + feature pipeline + the policy for off-recipe maps.
        "recipe": {"recipe_version": recipe_version, "map": desc["map"], "sh": desc["sh"], "features": spec,
                   "off_recipe": desc.get("off_recipe", "refuse")},
        "scaler": {"mean": mean.tolist(), "scale": scale.tolist()},
        "svm": {"type": "c_svc", "kernel": "rbf", "C": float(svc.C), "gamma": float(svc._gamma),
                "n_features": n_features, "n_classes": k, "labels": list(range(k)),
                "n_sv": [int(n) for n in svc.n_support_], "support_vectors": svc.support_vectors_.tolist(),
                "sv_coef": sv_coef.tolist(), "rho": rho.tolist(),
                "prob_a": np.asarray(svc.probA_, float).tolist(), "prob_b": np.asarray(svc.probB_, float).tolist()},
        "training": train,
    }
    payload = json.loads(dumps(payload))  # Grisu-safe numbers (wish_model_json.grisu_safe), as they will be read
    return {"format": FORMAT_NAME, "format_version": FORMAT_VERSION, "payload": payload,
            "payload_sha256": seal(payload)}


def write_model(doc: dict[str, Any], path: str | Path) -> None:
    """Writes the document (pretty, sorted keys, the sealed numbers verbatim)."""
    Path(path).write_text(dumps(doc, indent=1) + "\n", encoding="utf-8")


def read_model(path: str | Path, check_seal: bool = True) -> dict[str, Any]:
    """Reads and checks a model file: format, version, and (``check_seal``) the seal.

    Python reproduces nlohmann's number printing only for the Grisu-safe numbers it writes itself, so the seal of a
    file written by `wish train` (arbitrary doubles) can only be checked by the C++ loader: pass ``check_seal=False``
    when merely copying settings out of such a file.
    """
    doc = json.loads(Path(path).read_text(encoding="utf-8"))
    if doc.get("format") != FORMAT_NAME or doc.get("format_version") not in READABLE_VERSIONS:
        raise ValueError(f"{path}: not a {FORMAT_NAME} file of version {', '.join(map(str, READABLE_VERSIONS))}"
                         f" (format {doc.get('format')!r}, version {doc.get('format_version')!r})")
    if check_seal and seal(doc["payload"]) != doc.get("payload_sha256"):
        raise ValueError(f"{path}: payload_sha256 does not match the content")
    if doc["format_version"] == 1:  # the C++ loader's migration (model_file.cpp migrate_v1_payload)
        p = doc["payload"]
        recipe = dict(p.pop("descriptor"))
        recipe.update({"features": p.pop("features"), "off_recipe": "accept_flagged", "recipe_version": 1})
        p["recipe"] = recipe
        doc["format_version"] = FORMAT_VERSION
        doc["payload_sha256"] = seal(p) if check_seal else ""
    return doc


# ---- prediction from the model file (libsvm's algorithm) -----------------------------------------------------------

def _multiclass_probability(r: np.ndarray) -> np.ndarray:
    """libsvm 3.24 ``multiclass_probability``: pairwise coupling (Wu, Lin & Weng 2004, method 2)."""
    k = r.shape[0]
    q = np.zeros((k, k))
    for t in range(k):
        q[t, t] = sum(r[j, t] ** 2 for j in range(k) if j != t)
        for j in range(k):
            if j != t:
                q[t, j] = -r[j, t] * r[t, j]
    p = np.full(k, 1.0 / k)
    qp = np.zeros(k)
    eps = 0.005 / k
    for _ in range(max(100, k)):
        pqp = 0.0
        for t in range(k):
            qp[t] = q[t] @ p
            pqp += p[t] * qp[t]
        if max(abs(qp[t] - pqp) for t in range(k)) < eps:
            break
        for t in range(k):
            diff = (-qp[t] + pqp) / q[t, t]
            p[t] += diff
            pqp = (pqp + diff * (diff * q[t, t] + 2 * qp[t])) / (1 + diff) / (1 + diff)
            for j in range(k):
                qp[j] = (qp[j] + diff * q[t, j]) / (1 + diff)
                p[j] /= 1 + diff
    return p


def predict_with_model(doc: dict[str, Any], xi: np.ndarray) -> list[dict[str, Any]]:
    """What the service answers for rows of ξ(0..Lmax): label (vote winner), probabilities, pairwise decisions."""
    p = doc["payload"]
    svm = p["svm"]
    x = (apply_feature_spec(xi, p["recipe"]["features"]) - np.asarray(p["scaler"]["mean"])) / np.asarray(p["scaler"]["scale"])
    sv = np.asarray(svm["support_vectors"], float)
    coef = np.asarray(svm["sv_coef"], float)
    rho = np.asarray(svm["rho"], float)
    n_sv = svm["n_sv"]
    k = svm["n_classes"]
    start = np.concatenate([[0], np.cumsum(n_sv)])
    prob_a, prob_b = np.asarray(svm["prob_a"], float), np.asarray(svm["prob_b"], float)
    out = []
    for row in x:
        kv = np.exp(-svm["gamma"] * np.sum((sv - row) ** 2, axis=1))
        dec, votes, pair = [], np.zeros(k, int), 0
        r = np.zeros((k, k))
        for i in range(k):
            for j in range(i + 1, k):
                si, sj = slice(start[i], start[i + 1]), slice(start[j], start[j + 1])
                d = coef[j - 1, si] @ kv[si] + coef[i, sj] @ kv[sj] - rho[pair]
                dec.append(float(d))
                votes[i if d > 0 else j] += 1
                if len(prob_a):
                    fapb = d * prob_a[pair] + prob_b[pair]
                    pr = math.exp(-fapb) / (1 + math.exp(-fapb)) if fapb >= 0 else 1 / (1 + math.exp(fapb))
                    pr = min(max(pr, 1e-7), 1 - 1e-7)
                    r[i, j], r[j, i] = pr, 1 - pr
                pair += 1
        winner = int(np.argmax(votes))  # first maximum, as libsvm
        probs = _multiclass_probability(r) if len(prob_a) else np.array([])
        out.append({"label": p["classes"][svm["labels"][winner]], "decision": dec,
                    "probabilities": dict(zip(p["classes"], probs.tolist()))})
    return out


# ---- command line ---------------------------------------------------------------------------------------------------

def _labels_for(files: Sequence[str], own: list[str] | None, args: argparse.Namespace) -> list[str]:
    if args.labels:
        table: dict[str, str] = {}
        with open(args.labels, newline="", encoding="utf-8") as f:
            for r in csv.DictReader(f):
                lab = r.get("label") or r.get("class")
                if r.get("file") and lab and r.get("status", "ok") in ("ok", ""):
                    table[r["file"]] = lab
                    table.setdefault(Path(r["file"]).name, lab)
                    table.setdefault(Path(r["file"]).stem, lab)
        out = [table.get(f) or table.get(Path(f).name) or table.get(Path(f).stem) or "" for f in files]
    elif args.labels_from_folder:
        out = [Path(f).parent.name for f in files]
    elif own is not None:
        out = list(own)
    else:
        raise SystemExit("no labels: give --labels FILE, --labels-from-folder, or a CSV with a label column")
    missing = [f for f, lab in zip(files, out) if not lab]
    if missing:
        raise SystemExit(f"{len(missing)} rows have no label, e.g. {missing[0]}")
    return out


def _descriptor(args: argparse.Namespace) -> dict[str, Any] | None:
    if getattr(args, "descriptor_from", None):
        return descriptor_of(read_model(args.descriptor_from, check_seal=False))
    return None


def cmd_train(args: argparse.Namespace) -> int:
    from sklearn.model_selection import GridSearchCV, StratifiedShuffleSplit
    from sklearn.pipeline import Pipeline
    from sklearn.preprocessing import StandardScaler
    from sklearn.svm import SVC

    files, xi, own = read_describe_csv(args.descriptors)
    y = _labels_for(files, own, args)
    spec = feature_spec(args.l_max if args.l_max is not None else xi.shape[1] - 1, args.l_min, args.scale, args.log)
    x = apply_feature_spec(xi, spec)
    pipe = Pipeline([("scale", StandardScaler()), ("svm", SVC(kernel="rbf", probability=True, random_state=0))])
    training: dict[str, Any] = {"dataset_sha256": hashlib.sha256(Path(args.descriptors).read_bytes()).hexdigest()}
    if args.C is not None and args.gamma is not None:
        pipe.set_params(svm__C=args.C, svm__gamma=args.gamma).fit(x, y)
    else:  # the paper's grid, one decade per step, scored by StratifiedShuffleSplit with a fixed seed
        grid = {"svm__C": [10.0 ** e for e in range(-2, 11)], "svm__gamma": [10.0 ** e for e in range(-9, 4)]}
        search = GridSearchCV(pipe, grid, cv=StratifiedShuffleSplit(n_splits=5, test_size=0.2, random_state=0),
                              n_jobs=1).fit(x, y)
        pipe = search.best_estimator_
        training["grid_score"] = float(search.best_score_)
    doc = pipeline_to_model(pipe, spec, descriptor=_descriptor(args), lmax=args.lmax, name=args.name,
                            version=args.version, training=training)
    write_model(doc, args.out)
    if args.save_pipeline:
        with open(args.save_pipeline, "wb") as f:
            pickle.dump(pipe, f)
    svc = pipe.steps[1][1]
    print(f"wrote {args.out}: {len(svc.classes_)} classes, {len(svc.support_vectors_)} support vectors, "
          f"C={svc.C:g} gamma={svc._gamma:g}, features {spec['names'][0]}..{spec['names'][-1]}")
    return 0


def cmd_convert(args: argparse.Namespace) -> int:
    with open(args.pipeline, "rb") as f:
        pipe = pickle.load(f)  # noqa: S301 - the user's own notebook output
    n = pipe.steps[0][1].mean_.shape[0]
    l_max = args.l_max if args.l_max is not None else args.l_min + n - 1
    spec = feature_spec(l_max, args.l_min, args.scale, args.log)
    doc = pipeline_to_model(pipe, spec, descriptor=_descriptor(args), lmax=args.lmax, name=args.name,
                            version=args.version)
    write_model(doc, args.out)
    print(f"wrote {args.out}")
    return 0


def cmd_check(args: argparse.Namespace) -> int:
    doc = read_model(args.model)
    files, xi, _ = read_describe_csv(args.descriptors)
    preds = predict_with_model(doc, xi)
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["file", "label"] + [f"prob_{c}" for c in doc["payload"]["classes"]])
    for f, p in zip(files, preds):
        w.writerow([f, p["label"]] + [f"{p['probabilities'].get(c, 0):.6f}" for c in doc["payload"]["classes"]])
    if args.pipeline:
        with open(args.pipeline, "rb") as fh:
            pipe = pickle.load(fh)  # noqa: S301
        ref = pipe.predict(apply_feature_spec(xi, doc["payload"]["recipe"]["features"]))
        bad = sum(1 for a, b in zip(preds, ref) if a["label"] != b)
        print(f"# {len(files) - bad}/{len(files)} labels agree with the pipeline", file=sys.stderr)
        return 1 if bad else 0
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)

    def model_args(p: argparse.ArgumentParser) -> None:
        p.add_argument("--out", "-o", required=True, help="model file to write (.json)")
        p.add_argument("--l-min", type=int, default=1, help="first xi(l) used (default 1)")
        p.add_argument("--l-max", type=int, help="last xi(l) used (default: all in the CSV / the pipeline's width)")
        p.add_argument("--scale", choices=["none", "xi1"], default="none", help="xi(l)/xi(1) normalisation")
        p.add_argument("--log", action="store_true", help="natural log of the (normalised) energies")
        p.add_argument("--lmax", type=int, help="descriptor Lmax the CSV was computed with (default: --l-max)")
        p.add_argument("--descriptor-from", help="copy the descriptor settings from this model file")
        p.add_argument("--name", default="sklearn-svm", help="model name (the service's ?model=)")
        p.add_argument("--version", default="1")

    t = sub.add_parser("train", help="fit Pipeline(StandardScaler, SVC rbf) on a describe CSV and convert it")
    t.add_argument("descriptors")
    t.add_argument("--labels", help="CSV with file,label columns")
    t.add_argument("--labels-from-folder", action="store_true", help="label = parent folder of each file")
    t.add_argument("--C", type=float)
    t.add_argument("--gamma", type=float)
    t.add_argument("--save-pipeline", help="also pickle the fitted Pipeline here")
    model_args(t)
    c = sub.add_parser("convert", help="convert a pickled fitted Pipeline")
    c.add_argument("pipeline")
    model_args(c)
    k = sub.add_parser("check", help="predict a describe CSV with a model file (numpy libsvm), compare")
    k.add_argument("model")
    k.add_argument("descriptors")
    k.add_argument("--pipeline", help="pickled Pipeline to compare labels with")
    args = ap.parse_args(argv)
    return {"train": cmd_train, "convert": cmd_convert, "check": cmd_check}[args.cmd](args)


if __name__ == "__main__":
    sys.exit(main())
