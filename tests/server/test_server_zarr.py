"""OME-Zarr label images uploaded to /v1/describe as the zip of their store (zarr's ZipStore layout, written by
Debian's python3-zarr through tests/testing/ome_zarr_writer.py): detected by content, one entry per object exactly as
the NIfTI upload of the same labels gives (ids, voxel counts, centroids, ξ), validated against proto/openapi.json;
?label_image= and ?level= choose the label image and the multiscale level; a store that is not one 3-D label image is
a 400 naming the axis."""
import os
import shutil
import tempfile
import unittest

import numpy as np
import zarr

import ome_zarr_writer
import synthetic_volume as sv
import wish_server_harness as h

SKIP = None if os.path.exists(h.WISH_BIN) else "wish binary not found at %s (set WISH_BIN)" % h.WISH_BIN


def by_label(body):
    return {o["label_id"]: o for o in body["objects"]}


@unittest.skipIf(SKIP, SKIP or "")
class ServerZarrTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-zarr-")
        cls.server = h.Server(models_dir=h.models_dir_with_default(cls.tmp), args=["--workers", "2"])
        labels, cls.counts = sv.ellipsoid_scene()
        cls.nii = sv.nifti_bytes(labels, spacing=(1.0, 1.0, 1.0), units=3)
        cls.zyx = np.frombuffer(labels, dtype="u1").reshape(tuple(reversed(sv.DIMS)))
        path = os.path.join(cls.tmp, "scene.zarr.zip")
        ome_zarr_writer.write_store(path, cls.zyx, zip_store=True, spacing_xyz=(1.0, 1.0, 1.0), unit="um",
                                    codec="zstd", other_labels=("nuclei",), chunks=(10, 12, 20))
        with open(path, "rb") as f:
            cls.zip = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def describe(self, data, query="", content_type="application/zip"):
        r = self.server.post_mesh("/v1/describe" + query, data, content_type=content_type)
        return r, r.json()

    def test_a_store_zip_gives_the_objects_of_the_nifti(self):
        r0, nifti = self.describe(self.nii, "?lmax=6&method=cmcf", content_type="application/octet-stream")
        r1, body = self.describe(self.zip, "?lmax=6&method=cmcf&label_image=cells")
        self.assertEqual(r1.status, r0.status, body)
        h.validate("VolumeResult", body)
        self.assertEqual(body["volume"]["format"], "ome-zarr")
        self.assertEqual(body["volume"]["dims"], list(sv.DIMS))
        self.assertEqual(body["volume"]["unit"], "um")
        a, b = by_label(nifti), by_label(body)
        self.assertEqual(sorted(b), sorted(a))
        for label, count in self.counts.items():
            self.assertEqual(b[label]["object"]["voxel_count"], count, label)  # counted independently (numpy)
            for o in (a[label]["object"], b[label]["object"]):
                o.pop("timings", None)  # stage times differ from run to run
            self.assertEqual(b[label]["object"], a[label]["object"], label)
            self.assertEqual(b[label]["status"], a[label]["status"], label)
            if "result" in a[label]:
                np.testing.assert_allclose(b[label]["result"]["descriptor"]["invariants"],
                                           a[label]["result"]["descriptor"]["invariants"], rtol=1e-9, atol=1e-12)

    def test_multipart_part_and_level(self):
        r = self.server.post_multipart("/v1/describe?label_image=cells&level=1&lmax=4&method=cmcf",
                                       [("mesh", "scene.zarr.zip", self.zip)])
        body = r.json()
        h.validate("BatchResponse", body)
        volume = body["results"][0]["result"]
        self.assertEqual(volume["volume"]["dims"], [(n + 1) // 2 for n in sv.DIMS])
        small = self.zyx[::2, ::2, ::2]
        ids, counts = np.unique(small[small > 0], return_counts=True)
        # Every label of the level is an object, or a speck (under 8 voxels at this level) listed with its reason.
        kept = {o["label_id"]: o["object"]["voxel_count"] for o in volume["objects"]}
        specks = {d["label_id"]: d["voxel_count"] for d in volume["volume"]["dropped_objects"]}
        self.assertEqual({**kept, **specks}, dict(zip(ids.tolist(), counts.tolist())))
        self.assertTrue(all(d["reason"] == "speck" and d["voxel_count"] < 8 for d in volume["volume"]["dropped_objects"]))

    def test_refusals_name_what_was_wrong(self):
        r, body = self.describe(self.zip, "?label_image=golgi")
        self.assertEqual(r.status, 400, body)
        self.assertEqual(body["error"]["code"], "invalid_parameter")
        self.assertIn("nuclei, cells", body["error"]["message"])
        r, body = self.describe(self.zip, "?label_image=cells&level=5")
        self.assertEqual((r.status, body["error"]["code"]), (400, "invalid_parameter"))
        r, body = self.describe(self.zip, "?label_image=a/b")
        self.assertEqual((r.status, body["error"]["code"]), (400, "invalid_parameter"))
        # Two channels in one label array: not one 3-D label image.
        path = os.path.join(self.tmp, "two.zarr")
        ome_zarr_writer.write_store(path, self.zyx, extra_axes=(("c", "channel"),), codec="zlib")
        array = zarr.open(os.path.join(path, "labels", "cells", "0"), mode="r+")
        array.resize((2,) + self.zyx.shape)
        from wish_client.client import zip_zarr_store
        r, body = self.describe(zip_zarr_store(path))
        self.assertEqual((r.status, body["error"]["code"]), (400, "invalid_volume"), body)
        self.assertIn("axis 'c' has size 2", body["error"]["message"])
        # A zip that holds no zarr store is not a volume (nor a mesh).
        import io
        import zipfile
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w") as z:
            z.writestr("notes.txt", "hello")
        r, body = self.describe(buf.getvalue())
        self.assertEqual(r.status, 415, body)


if __name__ == "__main__":
    unittest.main()
