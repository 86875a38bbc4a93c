"""The Slurm batch runner (clients/slurm/wish_slurm.py) on a real single-node Slurm (scripts/test-slurm.sh starts it):

* a manifest of meshes is cut into shards, an `sbatch --array` job describes them, a dependent job merges one CSV;
* a shard with a broken mesh fails, the merge refuses and names it, the other shards' outputs are kept;
* after the mesh is fixed, a re-run submits only the failed shard (the others' attempt counts stay at 1) and the merge
  writes every mesh in manifest order with the values of a single `wish describe --csv` run over the whole manifest.

Skipped without SLURM_CONF (a running cluster) and WISH_BIN.
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
WISH_BIN = os.environ.get("WISH_BIN", "")
RUNNER = SOURCE / "clients" / "slurm" / "wish_slurm.py"
N_MESHES, N_SHARDS, BROKEN_AT = 12, 4, 7   # the broken mesh is in shard 2 (meshes 6..8)
SOURCES = ["sphere.off", "ellipsoid.off", "cube-meshed.off"]
LMAX = 8


def _skip() -> str | None:
    if not os.environ.get("SLURM_CONF"):
        return "SLURM_CONF is not set: run scripts/test-slurm.sh (it starts a single-node Slurm)"
    if not WISH_BIN or not Path(WISH_BIN).exists():
        return "WISH_BIN is not set or missing"
    return None


def deterministic(row: dict[str, str]) -> dict[str, str]:
    """A describe row without its timings (t_*), which differ from run to run."""
    return {k: v for k, v in row.items() if not k.startswith("t_")}


def read_csv(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


@unittest.skipIf(_skip(), _skip() or "")
class SlurmRunnerTest(unittest.TestCase):
    def setUp(self) -> None:
        self.tmp = Path(tempfile.mkdtemp(prefix="wish-slurm-"))
        self.addCleanup(shutil.rmtree, self.tmp, True)
        meshes = self.tmp / "meshes"
        meshes.mkdir()
        names = []
        for i in range(N_MESHES):
            src = SOURCE / "data" / "meshes" / SOURCES[i % len(SOURCES)]
            name = f"{i:03d}_{src.name}"
            if i == BROKEN_AT:
                (meshes / name).write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")   # truncated: 3 vertices announced, 2 given
            else:
                shutil.copyfile(src, meshes / name)
            names.append(name)
        # Manifest order is not file-name order: the merge must follow the manifest.
        order = names[::2] + names[1::2]
        self.broken = meshes / names[BROKEN_AT]
        self.broken_shard = order.index(names[BROKEN_AT]) * N_SHARDS // N_MESHES
        self.manifest = self.tmp / "manifest.txt"
        self.manifest.write_text("# meshes, relative to this file\n" + "".join(f"meshes/{n}\n" for n in order))
        self.order = [str((meshes / n).resolve()) for n in order]
        self.workdir = self.tmp / "run"

    def submit(self) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, str(RUNNER), "submit", str(self.manifest), "--workdir",
                               str(self.workdir), "--shards", str(N_SHARDS), "--wish", WISH_BIN, "--lmax", str(LMAX),
                               "--sbatch-arg=--time=10", "--wait"], capture_output=True, text=True, timeout=900)

    def attempts(self) -> list[int]:
        return [len((self.workdir / "attempts" / f"{i:04d}").read_text().splitlines())
                if (self.workdir / "attempts" / f"{i:04d}").exists() else 0 for i in range(N_SHARDS)]

    def test_shards_merge_in_manifest_order_and_a_rerun_redoes_only_the_failed_shard(self) -> None:
        t0 = time.monotonic()
        first = self.submit()
        first_seconds = time.monotonic() - t0
        self.assertNotEqual(first.returncode, 0, first.stdout)
        self.assertIn(f"shard(s) failed [{self.broken_shard}]", first.stdout)
        self.assertIn("array job", first.stdout)
        self.assertFalse((self.workdir / "merged.csv").exists())
        self.assertEqual(self.attempts(), [1] * N_SHARDS)
        status = json.loads(subprocess.run([sys.executable, str(RUNNER), "status", str(self.workdir)],
                                           capture_output=True, text=True, timeout=60).stdout)
        self.assertEqual(status["failed"], [self.broken_shard])
        self.assertEqual(status["done"], [i for i in range(N_SHARDS) if i != self.broken_shard])

        shutil.copyfile(SOURCE / "data" / "meshes" / "sphere.off", self.broken)   # the mesh fixed
        t0 = time.monotonic()
        second = self.submit()
        second_seconds = time.monotonic() - t0
        self.assertEqual(second.returncode, 0, second.stdout + second.stderr)
        self.assertIn(f"1 of {N_SHARDS} shards ({self.broken_shard})", second.stdout)
        self.assertEqual(self.attempts(), [2 if i == self.broken_shard else 1 for i in range(N_SHARDS)])

        merged = read_csv(self.workdir / "merged.csv")
        self.assertEqual([r["file"] for r in merged], self.order)
        single = subprocess.run([WISH_BIN, "describe", "--csv", "--lmax", str(LMAX), *self.order],
                                capture_output=True, text=True, timeout=600,
                                env=dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1"))
        self.assertEqual(single.returncode, 0, single.stderr)
        reference = list(csv.DictReader(single.stdout.splitlines()))
        self.assertEqual([deterministic(r) for r in merged], [deterministic(r) for r in reference])
        print(f"\nslurm: {N_MESHES} meshes in {N_SHARDS} shards: first run {first_seconds:.1f} s (shard "
              f"{self.broken_shard} failed), re-run of that shard {second_seconds:.1f} s", file=sys.stderr)


if __name__ == "__main__":
    unittest.main()
