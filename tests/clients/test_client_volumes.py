"""The Python client and the batch CLI with label volumes, against the real `wish serve`: classify_volume /
describe_volume parse one entry per object keyed by label id, and `wish-client classify` writes one row per object
(resumable). The volume is made here (tests/testing/synthetic_volume.py: two ellipsoids, a small ball, a border box,
a lattice of genus 81)."""

from __future__ import annotations

import contextlib
import csv
import io
import os
import shutil
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))

import synthetic_volume as sv  # noqa: E402
import wish_server_harness as h  # noqa: E402

from wish_client import WishClient, WishServerError  # noqa: E402
from wish_client.batch import expand_paths, read_records  # noqa: E402
from wish_client.cli import EXIT_FAILED, main  # noqa: E402

SKIP = None if os.path.exists(h.WISH_BIN) else f"wish binary not found at {h.WISH_BIN} (set WISH_BIN)"
MESH = os.path.join(h.SOURCE_DIR, "data", "meshes", "ellipsoid.off")


def run_cli(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


@unittest.skipIf(SKIP or not os.path.exists(h.DEFAULT_MODEL), SKIP or "no default model")
class ClientVolumeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls) -> None:
        cls.tmp = Path(tempfile.mkdtemp(prefix="wish-client-volume-"))
        cls.server = h.Server(models_dir=h.models_dir_with_default(str(cls.tmp)), args=["--workers", "2"])
        cls.url = f"http://127.0.0.1:{cls.server.port}"
        labels, cls.counts = sv.ellipsoid_scene()
        cls.volume = cls.tmp / "cells.nii.gz"
        cls.volume.write_bytes(sv.nifti_bytes(labels, gz=True))

    @classmethod
    def tearDownClass(cls) -> None:
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_describe_volume_threshold_and_the_input_decision(self) -> None:
        soft = sv.soft_ball(28)
        path = self.tmp / "soft.nii"
        path.write_bytes(sv.nifti_bytes(soft, dims=(28, 28, 28)))
        client = WishClient(self.url)
        r = client.describe_volume(path, lmax=4, method="cmcf")
        self.assertEqual((r.volume["input"]["kind"], r.volume["input"]["threshold"]), ("soft_mask", 127.5))
        self.assertEqual([o.object["voxel_count"] for o in r.objects], [sum(1 for v in soft if v >= 127.5)])
        r = client.describe_volume(path, threshold=200, lmax=4, method="cmcf")
        self.assertEqual(r.volume["input"]["threshold"], 200)
        self.assertEqual([o.object["voxel_count"] for o in r.objects], [sum(1 for v in soft if v >= 200)])

    def test_classify_volume_one_entry_per_object(self) -> None:
        r = WishClient(self.url).classify_volume(self.volume, min_voxels=20)
        self.assertEqual(r.name, "cells.nii.gz")
        self.assertEqual([o.label_id for o in r.objects], [1, 2, 4, 5])  # label 3 is under 20 voxels
        self.assertEqual(r.volume["dropped"]["small"], 1)
        objects = r.by_label()
        for label in (1, 2, 4):
            self.assertTrue(objects[label].ok, objects[label].error)
            self.assertEqual(objects[label].object["voxel_count"], self.counts[label])
            self.assertTrue(objects[label].result.label)
            self.assertEqual(objects[label].result.name, f"cells.nii.gz#{label}")
        self.assertTrue(objects[4].object["truncated"])
        self.assertFalse(objects[5].ok)
        self.assertEqual((objects[5].status, objects[5].error.code), (422, "genus_nonzero"))

    def test_describe_volume_with_spacing(self) -> None:
        r = WishClient(self.url).describe_volume(self.volume, labels=[2], spacing=(0.5, 0.5, 0.5), unit="um")
        self.assertEqual(r.volume["spacing"], [0.5, 0.5, 0.5])
        (o,) = r.objects
        self.assertEqual(o.label_id, 2)
        self.assertAlmostEqual(o.object["surface"]["voxel_volume"], self.counts[2] * 0.125, delta=1e-9)
        self.assertEqual(len(o.result.invariants), o.result.lmax + 1)

    def test_unreadable_volume_raises(self) -> None:
        with self.assertRaises(WishServerError) as ctx:
            WishClient(self.url).classify_volume(("broken.nii", self.volume.read_bytes()[:60]))
        self.assertGreaterEqual(ctx.exception.status, 400)

    def test_batch_cli_writes_one_row_per_object_and_resumes(self) -> None:
        folder = self.tmp / "batch"
        folder.mkdir(exist_ok=True)
        shutil.copy(self.volume, folder / "cells.nii.gz")
        shutil.copy(MESH, folder / "ellipsoid.off")
        self.assertEqual([os.path.basename(p) for p in expand_paths([folder])], ["cells.nii.gz", "ellipsoid.off"])
        out = self.tmp / "rows.csv"
        code, _, err = run_cli("classify", str(folder), "--server", self.url, "--out", str(out), "--no-progress",
                               "--min-voxels", "20", "--labels", "1,2,3,5")
        self.assertEqual(code, EXIT_FAILED, err)  # the lattice is refused, so the run reports a failure
        with out.open(newline="") as f:
            rows = list(csv.DictReader(f))
        volume_rows = [r for r in rows if r["file"].endswith("cells.nii.gz")]
        self.assertEqual([r["label_id"] for r in volume_rows], ["1", "2", "5"])
        self.assertEqual([r["status"] for r in volume_rows], ["ok", "ok", "error"])
        self.assertEqual(volume_rows[2]["error_code"], "genus_nonzero")
        self.assertEqual([int(r["voxel_count"]) for r in volume_rows], [self.counts[1], self.counts[2], self.counts[5]])
        self.assertEqual({r["truncated"] for r in volume_rows}, {"false"})
        (mesh_row,) = [r for r in rows if r["file"].endswith("ellipsoid.off")]
        self.assertEqual((mesh_row["status"], mesh_row["label_id"]), ("ok", ""))  # volume options not sent with it
        # Resume: the mesh is done and skipped; the volume (one object failed) is redone and its rows replaced.
        code, out_text, _ = run_cli("classify", str(folder), "--server", self.url, "--out", str(out), "--no-progress",
                                    "--min-voxels", "20", "--labels", "1,2", "--summary-json")
        self.assertEqual(code, 0)
        self.assertIn('"skipped_already_done": 1', out_text)
        records = read_records(out)
        self.assertEqual(sorted((os.path.basename(r.file), r.label_id) for r in records),
                         [("cells.nii.gz", "1"), ("cells.nii.gz", "2"), ("ellipsoid.off", "")])


    def test_batch_cli_writes_one_error_row_for_a_volume_with_no_object_left(self) -> None:
        out = self.tmp / "none.csv"
        code, _, err = run_cli("classify", str(self.volume), "--server", self.url, "--out", str(out), "--no-progress",
                               "--labels", "99")  # no such label: every object found is dropped
        self.assertEqual(code, EXIT_FAILED, err)
        (row,) = read_records(out)
        self.assertEqual((row.status, row.error_code, row.label_id), ("error", "no_objects", ""))
        self.assertIn(f"{len(self.counts)} found", row.error_message)  # the server's sentence, with its counts

if __name__ == "__main__":
    unittest.main()
