#!/usr/bin/python3
"""numpy.linalg.lstsq on the regularised weighted SH least-squares problem written by bench/sh_fit_bench.cpp.

usage: /usr/bin/python3 bench/sh_fit_numpy.py DIR n k nu
DIR holds raw float64 files: Y.bin (n x k, column-major: the real SH basis at the points), X.bin (n x 3,
column-major), w.bin (n weights summing to 1), r.bin (k penalties l^2 (l+1)^2). Solves
    min_C || [sqrt(w) Y; sqrt(nu r) I] C - [sqrt(w) X; 0] ||_F
with numpy.linalg.lstsq (LAPACK gelsd, SVD based), writes C (k x 3, column-major) to DIR/C.bin and prints the
best-of-3 wall time of the lstsq call in seconds.
"""
import sys
import time

import numpy as np


def main():
    d, n, k, nu = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    Y = np.fromfile(f"{d}/Y.bin", dtype=np.float64).reshape((n, k), order="F")
    X = np.fromfile(f"{d}/X.bin", dtype=np.float64).reshape((n, 3), order="F")
    w = np.fromfile(f"{d}/w.bin", dtype=np.float64)
    r = np.fromfile(f"{d}/r.bin", dtype=np.float64)
    sw = np.sqrt(w)[:, None]
    A = np.vstack([sw * Y, np.diag(np.sqrt(nu * r))])
    B = np.vstack([sw * X, np.zeros((k, 3))])
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        C, *_ = np.linalg.lstsq(A, B, rcond=None)
        best = min(best, time.perf_counter() - t0)
    np.asfortranarray(C).ravel(order="F").tofile(f"{d}/C.bin")
    print(best)


if __name__ == "__main__":
    main()
