#!/usr/bin/env python3
"""Label volume -> meshes benchmark: runs `wish mesh-labels` on each volume (one process per volume, so the memory
peak is per volume), then `wish describe --csv` on a sample of the meshes, and prints seconds per object and per
volume split into extraction, surface, smoothing, decimation and describe, with the peak RSS.

  OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 python3 bench/label_volume_bench.py --wish build/release/cli/wish \\
      --spacing 16,16,15 --describe-sample 10 ../shared/data/urocell/lyso/binary/*.nii.gz
Times come from objects.csv (per-stage timers in core/volume/object_surface.cpp); read + object finding is the
wall time minus the per-object stages. Absolute times drift on a shared machine: compare rows of one run."""
import argparse
import csv
import os
import resource
import subprocess
import sys
import tempfile
import time


def run_volume(wish, path, spacing, out):
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t0 = time.monotonic()
    cmd = [wish, 'mesh-labels', path, '--out', out, '--min-voxels', '500', '--drop-truncated', '--quiet']
    if spacing:
        cmd += ['--spacing', spacing, '--unit', 'nm']
    subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.monotonic() - t0
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss  # KiB, max over children so far
    rows = list(csv.DictReader(open(os.path.join(out, 'objects.csv'))))
    return wall, max(peak, before), rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('volumes', nargs='+')
    ap.add_argument('--wish', default='build/release/cli/wish')
    ap.add_argument('--spacing', default='')
    ap.add_argument('--describe-sample', type=int, default=10, help='meshes per volume to describe')
    a = ap.parse_args()
    stages = ['t_extraction', 't_surface', 't_smoothing', 't_decimation']
    print('| volume | objects | meshed | extraction s | surface s | smoothing s | decimation s | describe s/obj | '
          'read+find s | volume total s | peak RSS MiB |')
    print('|---|---|---|---|---|---|---|---|---|---|---|')
    grand = {s: 0.0 for s in stages}
    n_all = 0
    for v in a.volumes:
        with tempfile.TemporaryDirectory() as out:
            wall, peak, rows = run_volume(a.wish, v, a.spacing, out)
            sums = {s: sum(float(r[s]) for r in rows) for s in stages}
            meshed = [r for r in rows if r['status'] == 'meshed']
            sample = [os.path.join(out, r['file']) for r in meshed[:a.describe_sample]]
            describe = float('nan')
            if sample:
                d = subprocess.run([a.wish, 'describe', '--csv'] + sample, capture_output=True, text=True)
                lines = list(csv.DictReader(d.stdout.splitlines()))
                if lines:
                    describe = sum(float(r['t_total']) for r in lines) / len(lines)
            read_find = wall - sum(sums.values())
            total = wall + describe * len(meshed)
            print(f'| {os.path.basename(v)} | {len(rows)} | {len(meshed)} | ' + ' | '.join(f'{sums[s]:.2f}' for s in stages) +
                  f' | {describe:.2f} | {read_find:.2f} | {total:.1f} | {peak / 1024:.0f} |')
            for s in stages:
                grand[s] += sums[s]
            n_all += len(rows)
    if n_all:
        print('\nper object (mean over all objects): ' + ', '.join(f'{s[2:]} {grand[s] / n_all * 1000:.1f} ms' for s in stages))


if __name__ == '__main__':
    sys.exit(main())
