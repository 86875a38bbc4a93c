"""The one reader of ``wish describe --csv`` output (also ``wish train --save-descriptors``), used by the plots
(:mod:`wish_client.plots`) and by the scikit-learn converter (clients/convert/sklearn_to_wish.py).

Columns: ``file`` (or the first column), ``xi_0`` … ``xi_L`` (ξ(l), rotation invariants, l = 0..L), optionally
``label`` or ``class``; other columns (n_vertices, fit error, g_* global descriptors) are ignored here. A row whose ξ
cells are empty is a mesh that failed to describe: it is skipped, and counted in :attr:`DescribeTable.skipped`.
Standard library only.
"""

from __future__ import annotations

import csv
import os
import re
from dataclasses import dataclass

from .errors import WishInputError


@dataclass
class DescribeTable:
    files: list[str]
    xi: list[list[float]]            #: n × (L+1): ξ(0..L) of ``files[i]``
    labels: list[str] | None         #: from a ``label`` / ``class`` column, else None
    skipped: list[str]               #: files of rows without ξ (failed meshes)


def read_describe_csv(path: str | os.PathLike) -> DescribeTable:
    """Reads the CSV; raises :class:`WishInputError` (a ValueError) when it has no rows or no xi_0..xi_L columns."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise WishInputError(f"{path}: no rows")
    xi_cols = sorted((c for c in rows[0] if c and re.fullmatch(r"xi_\d+", c)), key=lambda c: int(c[3:]))
    if not xi_cols or [int(c[3:]) for c in xi_cols] != list(range(len(xi_cols))):
        raise WishInputError(f"{path}: expected columns xi_0..xi_L (the output of `wish describe --csv`)")
    file_col = "file" if "file" in rows[0] else next(iter(rows[0]))
    label_col = next((c for c in ("label", "class") if c in rows[0]), None)
    table = DescribeTable([], [], [] if label_col else None, [])
    for r in rows:
        try:
            values = [float(r[c]) for c in xi_cols]
        except (TypeError, ValueError):
            table.skipped.append(r.get(file_col) or "")
            continue
        table.files.append(r[file_col])
        table.xi.append(values)
        if table.labels is not None:
            table.labels.append(r[label_col] or "")
    return table
