"""The Python client with OME-Zarr stores, against the real `wish serve`: a store directory given to describe_volume
or to `wish-client classify` travels as its zip (wish_client.client.zip_zarr_store: the metadata and labels/ only)
and gives one entry per object, as the NIfTI of the same labels; folders holding stores expand to the stores, not to
their chunk files. The store is written by Debian's python3-zarr (tests/testing/ome_zarr_writer.py)."""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import sys
import tempfile
import unittest
import zipfile
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))

import ome_zarr_writer  # noqa: E402
import synthetic_volume as sv  # noqa: E402
import wish_server_harness as h  # noqa: E402

from wish_client import WishClient  # noqa: E402
from wish_client.batch import expand_paths, read_records  # noqa: E402
from wish_client.cli import main  # noqa: E402
from wish_client.client import is_volume_name, zip_zarr_store  # noqa: E402

SKIP = None if os.path.exists(h.WISH_BIN) else f"wish binary not found at {h.WISH_BIN} (set WISH_BIN)"


@unittest.skipIf(SKIP or not os.path.exists(h.DEFAULT_MODEL), SKIP or "no default model")
class ClientZarrTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls) -> None:
        cls.tmp = Path(tempfile.mkdtemp(prefix="wish-client-zarr-"))
        cls.server = h.Server(models_dir=h.models_dir_with_default(str(cls.tmp)), args=["--workers", "2"])
        cls.url = f"http://127.0.0.1:{cls.server.port}"
        labels, cls.counts = sv.ellipsoid_scene()
        cls.nifti = cls.tmp / "cells.nii"
        cls.nifti.write_bytes(sv.nifti_bytes(labels))
        zyx = np.frombuffer(labels, dtype="u1").reshape(tuple(reversed(sv.DIMS)))
        cls.store = cls.tmp / "data" / "cells.ome.zarr"
        ome_zarr_writer.write_store(str(cls.store), zyx, spacing_xyz=(1.0, 1.0, 1.0), unit="mm", codec="blosc")

    @classmethod
    def tearDownClass(cls) -> None:
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_zip_of_a_store_holds_its_labels_not_its_image(self) -> None:
        names = zipfile.ZipFile(io.BytesIO(zip_zarr_store(self.store))).namelist()
        self.assertIn(".zattrs", names)
        self.assertIn("labels/cells/0/.zarray", names)
        self.assertFalse([n for n in names if n.startswith("0/")], names)  # the intensity image's array
        self.assertTrue(is_volume_name(self.store))

    def test_describe_volume_of_a_store_directory_matches_the_nifti(self) -> None:
        client = WishClient(self.url)
        a = client.describe_volume(self.nifti, min_voxels=20, lmax=4, method="cmcf")
        b = client.describe_volume(self.store, min_voxels=20, lmax=4, method="cmcf", label_image="cells", level=0)
        self.assertEqual(b.name, "cells.ome.zarr")
        self.assertEqual(b.volume["format"], "ome-zarr")
        self.assertEqual([o.label_id for o in b.objects], [o.label_id for o in a.objects])
        for x, y in zip(a.objects, b.objects):
            self.assertEqual({k: v for k, v in x.object.items() if k != "timings"},
                             {k: v for k, v in y.object.items() if k != "timings"})
            self.assertEqual(x.object["voxel_count"], self.counts[x.label_id])

    def test_batch_cli_expands_a_folder_to_its_stores(self) -> None:
        self.assertEqual(expand_paths([self.tmp / "data"]), [str(self.store)])
        out = self.tmp / "out.csv"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            main(["classify", "--server", self.url, str(self.tmp / "data"), "--out", str(out), "--min-voxels", "20",
                  "--label-image", "cells", "--no-progress"])
        records = read_records(str(out))
        self.assertEqual(sorted({r.label_id for r in records}), ["1", "2", "4", "5"])


if __name__ == "__main__":
    unittest.main()
