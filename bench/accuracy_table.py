#!/usr/bin/env python3
"""Markdown table of bench/accuracy_table.sh's runs: one row per (labelled set, map method + area correction).

    python3 bench/accuracy_table.py WORK [SET ...]

Reads WORK/<set>.out (descriptor_accuracy_bench's stdout: meshes listed, refused before mapping, mapped per method
with the failure codes) and WORK/<set>.csv (nested-CV accuracy per feature family). Columns: meshes mapped by the
row's method of those listed, what the rest lost to, the meshes kept per class, xi alone / global / combined (mean +- std over the outer folds,
global on the same meshes as the row), and the issue's target: xi alone within 2 points of global or better
("xi ok"), combined above both ("comb ok"). A row the run's time bound cut off shows "-".
"""
import csv
import re
import sys
from pathlib import Path


def parse_out(path):
    listed, refused, mapped, failures, per_class = 0, 0, {}, {}, {}
    if not path.exists():
        return listed, refused, mapped, failures, per_class
    for line in path.read_text().splitlines():
        m = re.match(r"=== dataset \S+ \(.*\): (\d+) meshes used", line)
        if m:
            listed = int(m.group(1))
        m = re.match(r"maps \(.*\): (\d+) meshes refused before mapping(.*)", line)
        if m:
            refused = int(m.group(1))
        m = re.match(r"(\S+)\s+meshes per class:(.*?)( \(paired.*)?$", line)
        if m:
            per_class[m.group(1)] = m.group(2).strip()
            continue
        m = re.match(r"(\S+)\s+(\d+)/(\d+)\s+[\d.]+\s+[\d.]+\s+[\d.]+\s+(.*)$", line)
        if m:
            mapped[m.group(1)] = int(m.group(2))
            failures[m.group(1)] = m.group(4).strip()
    return listed, refused, mapped, failures, per_class


def parse_csv(path):
    scores = {}
    if not path.exists():
        return scores
    with path.open() as f:
        for row in csv.DictReader(f):
            scores[(row["method"], row["family"])] = (100 * float(row["accuracy_mean"]), 100 * float(row["accuracy_std"]))
    return scores


def fmt(score):
    return "-" if score is None else f"{score[0]:.1f} ± {score[1]:.1f}"


def main():
    work = Path(sys.argv[1])
    sets = sys.argv[2:] or ["demo", "raw_mc", "urocell", "hard"]
    print("| set | map | mapped / listed | lost (check × count) | kept per class | ξ alone | global | combined | ξ ≥ global − 2 | combined > both |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in sets:
        listed, refused, mapped, failures, per_class = parse_out(work / f"{name}.out")
        scores = parse_csv(work / f"{name}.csv")
        for method in mapped:
            xi = scores.get((method, "invariants"))
            glob = scores.get((method, "global"))
            comb = scores.get((method, "combined"))
            lost = failures[method]
            if refused:
                lost = f"{lost}; refused before mapping × {refused}" if lost != "-" else f"refused before mapping × {refused}"
            xi_ok = "-" if xi is None or glob is None else ("yes" if xi[0] >= glob[0] - 2 else "no")
            comb_ok = "-" if None in (xi, glob, comb) else ("yes" if comb[0] > max(xi[0], glob[0]) else "no")
            print(f"| {name} | {method} | {mapped[method]} / {listed} | {lost} | {per_class.get(method, '-')} | {fmt(xi)} | {fmt(glob)} | {fmt(comb)} | {xi_ok} | {comb_ok} |")


if __name__ == "__main__":
    main()
