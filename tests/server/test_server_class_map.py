"""`/v1/classify?output=labels` on a label volume (issue 39 item 3): the answer's VolumeResult carries the class map
in the upload's own format (base64, `class_map`) and each object's class_value; the map, decoded and read by
independent readers (python3-nibabel for NIfTI, python3-pil for TIFF, python3-zarr for the OME-Zarr zip), holds
each object's value on exactly its voxels. The Python client saves it. /v1/describe and mesh uploads refuse it.
The volume is the synthetic scene (tests/testing/synthetic_volume.py), made here."""
import base64
import io
import os
import shutil
import tempfile
import unittest
import zipfile

import numpy as np

import ome_zarr_writer
import synthetic_volume as sv
import wish_server_harness as h
from wish_client import WishClient

try:
    import nibabel
except ImportError:
    nibabel = None
try:
    from PIL import Image, ImageSequence
except ImportError:
    Image = None
import zarr

SKIP = None if os.path.exists(h.WISH_BIN) else "wish binary not found at %s (set WISH_BIN)" % h.WISH_BIN


@unittest.skipIf(SKIP, SKIP or "")
class ServerClassMapTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-class-map-")
        cls.server = h.Server(models_dir=h.models_dir_with_default(cls.tmp), args=["--workers", "2"])
        labels, _ = sv.ellipsoid_scene()
        nx, ny, nz = sv.DIMS
        cls.zyx = np.frombuffer(labels, dtype=np.uint8).reshape(nz, ny, nx)
        cls.nii = sv.nifti_bytes(labels, spacing=(0.5, 0.5, 1.0), units=3)

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def classify(self, data, query="?output=labels", content_type="application/octet-stream"):
        r = self.server.post_mesh("/v1/classify" + query, data, content_type=content_type)
        body = r.json()
        self.assertIn(r.status, (200, 207), r.body[:400])  # the lattice is refused: 207
        h.validate("VolumeResult", body)
        cm = body["class_map"]
        data = base64.b64decode(cm["data"])
        self.assertEqual(len(data), cm["bytes"])
        return body, cm, data

    def check(self, body, class_map_zyx):
        self.assertEqual(class_map_zyx.shape, self.zyx.shape)
        legend = {v["name"]: v["value"] for v in body["class_map"]["values"]}
        for o in body["objects"]:
            want = legend["refused"] if "error" in o else (
                legend["novel"] if o["result"]["prediction"]["novel"] else legend[o["result"]["prediction"]["label"]])
            self.assertEqual(o["class_value"], want, o["label_id"])
            self.assertEqual(np.unique(class_map_zyx[self.zyx == o["label_id"]]).tolist(), [want], o["label_id"])
        self.assertTrue((class_map_zyx[self.zyx == 0] == 0).all())

    @unittest.skipIf(nibabel is None, "needs python3-nibabel")
    def test_nifti_upload_gets_a_nifti_class_map(self):
        body, cm, data = self.classify(self.nii)
        self.assertEqual((cm["format"], cm["media_type"]), ("nifti", "application/gzip"))
        path = os.path.join(self.tmp, cm["filename"])
        with open(path, "wb") as f:
            f.write(data)
        img = nibabel.load(path)
        self.assertEqual(tuple(float(z) for z in img.header.get_zooms()), (0.5, 0.5, 1.0))
        self.check(body, np.transpose(np.asarray(img.dataobj), (2, 1, 0)))

    @unittest.skipIf(Image is None, "needs python3-pil")
    def test_tiff_upload_gets_a_tiff_class_map(self):
        buffer = io.BytesIO()
        pages = [Image.fromarray(page) for page in self.zyx]
        pages[0].save(buffer, format="TIFF", save_all=True, append_images=pages[1:])
        body, cm, data = self.classify(buffer.getvalue())
        self.assertEqual((cm["format"], cm["media_type"], cm["filename"][-4:]), ("tiff", "image/tiff", ".tif"))
        with Image.open(io.BytesIO(data)) as im:
            self.check(body, np.stack([np.array(f) for f in ImageSequence.Iterator(im)]))

    def test_ome_zarr_upload_gets_the_zip_of_a_labels_group(self):
        path = os.path.join(self.tmp, "scene.zarr.zip")
        ome_zarr_writer.write_store(path, self.zyx, zip_store=True, spacing_xyz=(0.5, 0.5, 1.0), unit="um",
                                    codec="zlib")
        with open(path, "rb") as f:
            body, cm, data = self.classify(f.read(), content_type="application/zip")
        self.assertEqual((cm["format"], cm["media_type"]), ("ome-zarr", "application/zip"))
        store = os.path.join(self.tmp, "class-map.zarr")
        with zipfile.ZipFile(io.BytesIO(data)) as z:
            z.extractall(store)
        root = zarr.open(store, mode="r")
        self.assertIn(cm["name"], root["labels"].attrs["labels"])
        self.assertIn("image-label", root["labels"][cm["name"]].attrs)
        self.check(body, np.asarray(root["labels"][cm["name"]]["0"]))

    def test_output_labels_is_refused_where_it_cannot_apply(self):
        r = self.server.post_mesh("/v1/describe?output=labels", self.nii)
        self.assertEqual((r.status, r.json()["error"]["code"]), (400, "invalid_parameter"))
        self.assertIn("needs a model", r.json()["error"]["message"])
        with open(os.path.join(h.SOURCE_DIR, "data", "meshes", "sphere.off"), "rb") as f:
            r = self.server.post_mesh("/v1/classify?output=labels", f.read())
        self.assertEqual((r.status, r.json()["error"]["code"]), (400, "invalid_parameter"))
        r = self.server.post_mesh("/v1/classify?output=png", self.nii)
        self.assertEqual(r.status, 400)
        # Without output=labels the answer has no class map.
        r = self.server.post_mesh("/v1/classify", self.nii)
        self.assertNotIn("class_map", r.json())

    @unittest.skipIf(nibabel is None, "needs python3-nibabel")
    def test_python_client_saves_the_class_map(self):
        client = WishClient("http://127.0.0.1:%d" % self.server.port, timeout=120)
        out = client.classify_volume(("scene.nii", self.nii), output="labels")
        self.assertEqual(out.class_map["format"], "nifti")
        self.assertNotIn("data", out.class_map)
        path = out.save_class_map(os.path.join(self.tmp, "saved.nii.gz"))
        self.check(out.raw, np.transpose(np.asarray(nibabel.load(str(path)).dataobj), (2, 1, 0)))


if __name__ == "__main__":
    unittest.main()
