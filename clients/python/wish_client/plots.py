"""Plots people want to look at (matplotlib Agg + scikit-learn, Debian python3-matplotlib / python3-sklearn).

    wish-client plot tsne      DESCRIPTORS.csv --labels LABELS --out tsne.png     (paper Fig. 8)
    wish-client plot spectrum  DESCRIPTORS.csv --labels LABELS --out spectrum.svg
    wish-client plot confusion --report training-report.json --out confusion.png
    wish-client plot confusion --predicted results.csv --labels truth.csv --out confusion.png

DESCRIPTORS.csv is the output of ``wish describe --csv`` (columns ``file``, ``n_vertices``, fit-error columns,
``xi_0`` .. ``xi_L``). Class labels come from, in order: ``--labels FILE`` (any CSV/JSON with ``file`` and ``label``
or ``class`` columns — a ``wish-client classify`` output qualifies), a ``label``/``class`` column of the descriptor
CSV, or ``--labels-from-folder`` (each mesh's parent folder name, the usual layout of a labelled data set). Files are
matched by path, then by file name, then by name without extension. The format follows ``--out``'s extension
(.png, .svg, .pdf).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .describe_csv import read_describe_csv
from .errors import WishInputError

#: Colours of the paper's six classes (Fig. 8 draws neurons green); other classes cycle through tab10.
CLASS_COLOURS = {"neuron": "#2ca02c", "astrocyte": "#1f77b4", "endothelium": "#d62728", "microglia": "#ff7f0e",
                 "pericyte": "#9467bd", "oligodendrocyte": "#8c564b"}


# ---- inputs --------------------------------------------------------------------------------------------------------

def read_descriptor_csv(path: str | os.PathLike) -> tuple[list[str], list[list[float]], list[str] | None]:
    """``(files, xi, labels)`` of ``wish describe --csv`` output (:func:`wish_client.describe_csv.read_describe_csv`;
    rows of failed meshes, without ξ, are not plottable and left out)."""
    table = read_describe_csv(path)
    return table.files, table.xi, table.labels


def read_labels(path: str | os.PathLike) -> dict[str, str]:
    """``file -> label`` from a CSV or JSON with ``file`` and ``label`` (or ``class``/``truth``) fields.

    Rows whose ``status`` is not ``ok`` (failed classifications) are ignored.
    """
    p = Path(path)
    if p.suffix.lower() == ".json":
        doc = json.loads(p.read_text(encoding="utf-8"))
        rows = doc.get("results", doc) if isinstance(doc, dict) else doc
        if isinstance(rows, dict):  # {"file": "label"}
            return {str(k): str(v) for k, v in rows.items()}
    else:
        with p.open(newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    out: dict[str, str] = {}
    for r in rows:
        if r.get("status", "ok") not in ("ok", ""):
            continue
        label = r.get("label") or r.get("class") or r.get("truth")
        if r.get("file") and label:
            out[str(r["file"])] = str(label)
    if not out:
        raise WishInputError(f"{path}: no (file, label) rows")
    return out


def match_labels(files: Sequence[str], labels: dict[str, str]) -> list[str | None]:
    """Looks each file up by full path, normalised path, file name, then name without extension."""
    tables: list[dict[str, str]] = [labels, {os.path.normpath(k): v for k, v in labels.items()},
                                    {os.path.basename(k): v for k, v in labels.items()},
                                    {Path(k).stem: v for k, v in labels.items()}]
    keys = [lambda f: f, os.path.normpath, os.path.basename, lambda f: Path(f).stem]
    out: list[str | None] = []
    for f in files:
        out.append(next((t[k(f)] for t, k in zip(tables, keys) if k(f) in t), None))
    return out


def _labelled(args: argparse.Namespace) -> tuple[list[str], Any, list[str]]:
    """Descriptor rows that have a label: ``(files, xi array, labels)``."""
    import numpy as np

    files, xi, own = read_descriptor_csv(args.descriptors)
    if args.labels:
        found = match_labels(files, read_labels(args.labels))
    elif args.labels_from_folder:
        found = [Path(f).parent.name or None for f in files]
    elif own is not None:
        found = [x or None for x in own]
    else:
        raise WishInputError("no class labels: give --labels FILE or --labels-from-folder "
                             "(or a descriptor CSV with a label column)")
    keep = [i for i, lab in enumerate(found) if lab]
    if len(keep) < 2:
        raise WishInputError(f"only {len(keep)} of {len(files)} descriptor rows have a label")
    return [files[i] for i in keep], np.asarray([xi[i] for i in keep], dtype=float), [str(found[i]) for i in keep]


def _colours(classes: Sequence[str]) -> dict[str, Any]:
    import matplotlib

    cycle = matplotlib.colormaps["tab10"].colors
    extra = iter(c for c in cycle if matplotlib.colors.to_hex(c) not in CLASS_COLOURS.values())
    out = {}
    for c in classes:
        out[c] = CLASS_COLOURS.get(c.lower()) or next(extra, "#7f7f7f")
    return out


def _figure():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig: Any, out: str | os.PathLike) -> None:
    suffix = Path(out).suffix.lower()
    if suffix not in (".png", ".svg", ".pdf"):
        raise WishInputError(f"--out must end in .png, .svg or .pdf, not {str(out)!r}")
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=150, bbox_inches="tight")


# ---- the plots -----------------------------------------------------------------------------------------------------

def tsne_embedding(xi: Any, l_min: int = 1, log: bool = True, perplexity: float | None = None,
                   seed: int = 0) -> Any:
    """2-D t-SNE of the energies ξ(l_min..L) (paper Fig. 8).

    Features: log10 of ξ (energies span decades; without it the low l dominate), then z-scored per column, as the
    classifier sees them. ``perplexity`` defaults to ``min(30, (n-1)/3)`` so small sets work. Deterministic for a
    given ``seed``.
    """
    import numpy as np
    from sklearn.manifold import TSNE
    from sklearn.preprocessing import StandardScaler

    x = np.asarray(xi, dtype=float)[:, l_min:]
    if log:
        x = np.log10(np.maximum(x, np.finfo(float).tiny))
    x = StandardScaler().fit_transform(x)
    n = x.shape[0]
    if n < 3:
        raise WishInputError(f"t-SNE needs at least 3 labelled shapes, got {n}")
    perp = perplexity if perplexity is not None else max(1.0, min(30.0, (n - 1) / 3.0))
    # Exact gradients are faster than Barnes-Hut for the few hundred shapes of a typical study.
    return TSNE(n_components=2, perplexity=perp, init="pca", learning_rate="auto", random_state=seed,
                method="exact" if n <= 500 else "barnes_hut").fit_transform(x)


def plot_tsne(xi: Any, labels: Sequence[str], out: str | os.PathLike, *, l_min: int = 1, log: bool = True,
              perplexity: float | None = None, seed: int = 0, title: str | None = None) -> None:
    """Scatter of the t-SNE embedding, one colour per class."""
    plt = _figure()
    emb = tsne_embedding(xi, l_min=l_min, log=log, perplexity=perplexity, seed=seed)
    classes = sorted(set(labels))
    colours = _colours(classes)
    fig, ax = plt.subplots(figsize=(6, 5))
    for c in classes:
        idx = [i for i, lab in enumerate(labels) if lab == c]
        ax.scatter(emb[idx, 0], emb[idx, 1], s=28, color=colours[c], label=f"{c} ({len(idx)})",
                   edgecolors="white", linewidths=0.5)
    lmax = len(xi[0]) - 1
    ax.set_title(title or f"t-SNE of rotation-invariant energies ξ({l_min}..{lmax})")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.legend(loc="best", fontsize=8, frameon=False)
    _save(fig, out)
    plt.close(fig)


def plot_spectrum(xi: Any, labels: Sequence[str], out: str | os.PathLike, *, l_min: int = 1,
                  normalise: bool = False, title: str | None = None) -> None:
    """ξ(l) per class: the median (line) and the 25–75 % band, log scale.

    ``normalise`` divides every spectrum by its ξ(1) first (scale-free shape spectrum).
    """
    import numpy as np

    plt = _figure()
    x = np.asarray(xi, dtype=float)
    if normalise:
        x = x / x[:, [1]]
    ls = np.arange(l_min, x.shape[1])
    classes = sorted(set(labels))
    colours = _colours(classes)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    lab = np.asarray(labels)
    for c in classes:
        rows = x[lab == c][:, l_min:]
        med = np.median(rows, axis=0)
        lo, hi = np.percentile(rows, 25, axis=0), np.percentile(rows, 75, axis=0)
        ax.plot(ls, med, "-o", ms=3, color=colours[c], label=f"{c} ({rows.shape[0]})")
        ax.fill_between(ls, lo, hi, color=colours[c], alpha=0.15, linewidth=0)
    ax.set_yscale("log")
    ax.set_xlabel("degree l")
    ax.set_ylabel("ξ(l) / ξ(1)" if normalise else "ξ(l)  [length²]")
    ax.set_xticks(ls if len(ls) <= 26 else ls[::max(1, len(ls) // 13)])
    ax.set_title(title or "Energy spectrum per class (median, 25–75 %)")
    ax.legend(fontsize=8, frameon=False)
    ax.grid(True, which="major", alpha=0.3)
    _save(fig, out)
    plt.close(fig)


def find_confusion(doc: Any) -> tuple[list[str], list[list[float]]]:
    """Finds ``(classes, matrix)`` in a training report (rows = true class, columns = predicted).

    Accepted shapes, anywhere in the JSON: ``{"confusion_matrix": [[..]], "classes": [..]}``,
    ``{"confusion_matrix": {"classes"|"labels": [..], "matrix"|"counts": [[..]]}}``, and
    ``{"confusion_matrix": {"true": {"pred": n}}}``.
    """
    def walk(node: Any, classes_hint: list[str] | None) -> tuple[list[str], list[list[float]]] | None:
        if isinstance(node, dict):
            hint = node.get("classes") or node.get("labels") or classes_hint
            for key, val in node.items():
                if "confusion" in key.lower():
                    if isinstance(val, list) and hint:
                        return list(map(str, hint)), val
                    if isinstance(val, dict):
                        inner_cls = val.get("classes") or val.get("labels") or hint
                        mat = val.get("matrix") or val.get("counts")
                        if mat is not None and inner_cls:
                            return list(map(str, inner_cls)), mat
                        if val and all(isinstance(v, dict) for v in val.values()):
                            cls = list(val)
                            return cls, [[val[t].get(p, 0) for p in cls] for t in cls]
            for val in node.values():
                found = walk(val, hint if isinstance(hint, list) else None)
                if found:
                    return found
        elif isinstance(node, list):
            for val in node:
                found = walk(val, classes_hint)
                if found:
                    return found
        return None

    found = walk(doc, None)
    if not found:
        raise WishInputError("no confusion matrix in the report (looked for a 'confusion_matrix' with classes)")
    classes, mat = found
    if len(mat) != len(classes) or any(len(r) != len(classes) for r in mat):
        raise WishInputError(f"confusion matrix is not {len(classes)}×{len(classes)}")
    return classes, mat


def plot_confusion(classes: Sequence[str], matrix: Any, out: str | os.PathLike, *, normalise: bool = False,
                   title: str | None = None) -> None:
    """The confusion matrix (rows = true class, columns = predicted), counts or row-normalised recall."""
    import numpy as np
    from sklearn.metrics import ConfusionMatrixDisplay

    plt = _figure()
    m = np.asarray(matrix, dtype=float)
    if normalise:
        m = m / np.maximum(m.sum(axis=1, keepdims=True), 1)
    fig, ax = plt.subplots(figsize=(1.0 + 0.9 * len(classes), 0.8 + 0.8 * len(classes)))
    disp = ConfusionMatrixDisplay(m if normalise else m.astype(int), display_labels=list(classes))
    disp.plot(ax=ax, cmap="Blues", colorbar=False, values_format=".2f" if normalise else "d",
              xticks_rotation=45)
    acc = float(np.trace(np.asarray(matrix, float)) / max(np.sum(matrix), 1))
    ax.set_title(title or f"Confusion matrix (accuracy {acc:.2f})")
    _save(fig, out)
    plt.close(fig)


# ---- command line --------------------------------------------------------------------------------------------------

def add_plot_parser(sub: Any) -> None:
    p = sub.add_parser("plot", help="t-SNE of invariants, ξ(l) spectrum per class, confusion matrix (PNG/SVG)",
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    kinds = p.add_subparsers(dest="plot", required=True, metavar="KIND")

    def labelled(q: argparse.ArgumentParser) -> None:
        q.add_argument("descriptors", help="CSV of `wish describe --csv`")
        q.add_argument("--labels", help="CSV/JSON with file + label (e.g. a `wish-client classify` output)")
        q.add_argument("--labels-from-folder", action="store_true", help="class = each mesh's parent folder name")
        q.add_argument("--l-min", type=int, default=1, help="first degree used (default 1: ξ(0) is the position)")
        q.add_argument("--out", "-o", required=True, help="image file (.png, .svg, .pdf)")
        q.add_argument("--title")

    t = kinds.add_parser("tsne", help="2-D t-SNE of log ξ(l) coloured by class (paper Fig. 8)")
    labelled(t)
    t.add_argument("--perplexity", type=float, help="default: min(30, (n-1)/3)")
    t.add_argument("--seed", type=int, default=0)
    t.add_argument("--no-log", action="store_true", help="use ξ itself rather than log10 ξ")

    s = kinds.add_parser("spectrum", help="ξ(l) per class: median and 25–75 %% band, log scale")
    labelled(s)
    s.add_argument("--normalise", action="store_true", help="divide each spectrum by its ξ(1)")

    c = kinds.add_parser("confusion", help="confusion matrix of a training report or of predictions vs truth")
    c.add_argument("--report", help="training report JSON (`wish train --report`)")
    c.add_argument("--predicted", help="a `wish-client classify` output (CSV/JSON)")
    c.add_argument("--labels", help="true labels (CSV/JSON with file + label), with --predicted")
    c.add_argument("--normalise", action="store_true", help="row-normalise (recall per class)")
    c.add_argument("--out", "-o", required=True, help="image file (.png, .svg, .pdf)")
    c.add_argument("--title")


def run_plot(args: argparse.Namespace) -> int:
    if args.plot in ("tsne", "spectrum"):
        _, xi, labels = _labelled(args)
        if args.plot == "tsne":
            plot_tsne(xi, labels, args.out, l_min=args.l_min, log=not args.no_log, perplexity=args.perplexity,
                      seed=args.seed, title=args.title)
        else:
            plot_spectrum(xi, labels, args.out, l_min=args.l_min, normalise=args.normalise, title=args.title)
    else:
        if args.report:
            classes, matrix = find_confusion(json.loads(Path(args.report).read_text(encoding="utf-8")))
        elif args.predicted and args.labels:
            from sklearn.metrics import confusion_matrix

            pred = read_labels(args.predicted)
            truth = read_labels(args.labels)
            files = list(pred)
            true_labels = match_labels(files, truth)
            pairs = [(t, pred[f]) for f, t in zip(files, true_labels) if t is not None]
            if not pairs:
                raise WishInputError("no predicted file has a true label")
            classes = sorted({t for t, _ in pairs} | {p for _, p in pairs})
            matrix = confusion_matrix([t for t, _ in pairs], [p for _, p in pairs], labels=classes).tolist()
        else:
            raise WishInputError("confusion needs --report, or --predicted with --labels")
        plot_confusion(classes, matrix, args.out, normalise=args.normalise, title=args.title)
    print(f"wrote {args.out}")
    return 0
