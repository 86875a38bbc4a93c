"""Label volume uploads on /v1/describe and /v1/classify: one result or one error per object, keyed by label id,
validated against proto/openapi.json (VolumeResult); volume parameters as `wish mesh-labels`; the volume limits.
The volumes are made here (tests/testing/synthetic_volume.py: ellipsoids, a small ball, a border box, a lattice of genus 81)."""
import math
import os
import shutil
import tempfile
import unittest

import synthetic_volume as sv
import wish_server_harness as h

SKIP = None if os.path.exists(h.WISH_BIN) else "wish binary not found at %s (set WISH_BIN)" % h.WISH_BIN
SPHERE_OFF = os.path.join(h.SOURCE_DIR, "data", "meshes", "sphere.off")


def by_label(body):
    return {o["label_id"]: o for o in body["objects"]}


@unittest.skipIf(SKIP, SKIP or "")
class ServerVolumeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-volume-")
        cls.models = h.models_dir_with_default(cls.tmp)
        cls.server = h.Server(models_dir=cls.models, args=["--workers", "2"])
        cls.labels, cls.counts = sv.ellipsoid_scene()
        cls.nii = sv.nifti_bytes(cls.labels, spacing=(1.0, 1.0, 1.0))

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def describe(self, data, query=""):
        r = self.server.post_mesh("/v1/describe" + query, data)
        return r, r.json()

    def test_one_entry_per_object_keyed_by_label_id(self):
        r, body = self.describe(self.nii)
        self.assertEqual(r.status, 207, body)  # the lattice is refused, the others not (test_server_volume_status.py)
        h.validate("VolumeResult", body)
        self.assertEqual(body["request_id"], r.header("X-Request-Id"))
        self.assertEqual(body["volume"]["format"], "nifti")
        self.assertEqual(body["volume"]["dims"], list(sv.DIMS))
        self.assertEqual(body["volume"]["objects_found"], 5)
        self.assertEqual([o["label_id"] for o in body["objects"]], [1, 2, 3, 4, 5])  # label-id order
        objects = by_label(body)
        for label, count in self.counts.items():
            self.assertEqual(objects[label]["object"]["voxel_count"], count, label)  # counted independently here
        # The ellipsoids are described, each with its descriptor and the request id; centroids in physical units.
        for label, centre in ((1, (12, 14, 12)), (2, (30, 18, 14))):
            o = objects[label]
            self.assertEqual(o["status"], 200, o)
            self.assertEqual(o["result"]["request_id"], body["request_id"])
            self.assertEqual(len(o["result"]["descriptor"]["invariants"]), o["result"]["descriptor"]["lmax"] + 1)
            for got, want in zip(o["object"]["centroid"], centre):
                self.assertAlmostEqual(got, want, delta=0.05)
            self.assertFalse(o["object"]["truncated"])
            self.assertEqual(o["object"]["genus"], 0)
            # The surface encloses about the voxel volume (marching surface + volume-preserving smoothing).
            s = o["object"]["surface"]
            self.assertLess(abs(s["volume"] / s["voxel_volume"] - 1), 0.1, s)
        # The border box is kept and flagged; the lattice is refused on its own, with its genus.
        self.assertTrue(objects[4]["object"]["truncated"])
        self.assertEqual(objects[5]["status"], 422)
        self.assertEqual(objects[5]["error"]["code"], "genus_nonzero")
        self.assertEqual(objects[5]["object"]["genus"], 81)
        self.assertEqual(body["counts"]["refused"], 1)
        self.assertEqual(body["counts"]["described"], body["counts"]["objects"] - 1)

    def test_gzip_nifti_is_the_same_volume(self):
        _, plain = self.describe(self.nii, "?labels=1,2")
        r, packed = self.describe(sv.nifti_bytes(self.labels, gz=True), "?labels=1,2")
        self.assertEqual(r.status, 200, packed)
        self.assertEqual([o["object"]["voxel_count"] for o in packed["objects"]],
                         [o["object"]["voxel_count"] for o in plain["objects"]])
        for a, b in zip(plain["objects"], packed["objects"]):
            self.assertEqual(a["result"]["descriptor"]["invariants"], b["result"]["descriptor"]["invariants"])

    def test_filters_mirror_mesh_labels(self):
        r, body = self.describe(self.nii, "?min_voxels=20&drop_truncated=true&labels=1,3,4,5")
        self.assertEqual(r.status, 207, body)  # 1 described, 5 (the lattice) refused
        self.assertEqual([o["label_id"] for o in body["objects"]], [1, 5])
        self.assertEqual(body["volume"]["dropped"], {"not_selected": 1, "speck": 0, "small": 1, "truncated": 1})

    def test_spacing_scales_the_surface(self):
        # Metamorphic: a uniform voxel size s scales lengths by s, areas by s^2, volumes by s^3 and the centroid by s.
        _, one = self.describe(self.nii, "?labels=1")
        r, two = self.describe(self.nii, "?labels=1&spacing=2,2,2&unit=um")
        self.assertEqual(r.status, 200, two)
        self.assertEqual(two["volume"]["spacing"], [2.0, 2.0, 2.0])
        self.assertEqual(two["volume"]["unit"], "um")
        a, b = one["objects"][0]["object"], two["objects"][0]["object"]
        self.assertAlmostEqual(b["surface"]["area"] / a["surface"]["area"], 4.0, delta=4e-3)
        self.assertAlmostEqual(b["surface"]["volume"] / a["surface"]["volume"], 8.0, delta=8e-3)
        for p, q in zip(a["centroid"], b["centroid"]):
            self.assertAlmostEqual(q, 2 * p, delta=1e-9)
        # The descriptor's energies are scale-normalised or not, but their ratios are not changed by a scale.
        xa = one["objects"][0]["result"]["descriptor"]["invariants"]
        xb = two["objects"][0]["result"]["descriptor"]["invariants"]
        for l in range(1, len(xa)):
            if xa[1] > 1e-12 and xa[l] > 1e-9 * xa[1]:
                self.assertAlmostEqual(xb[l] / xb[1], xa[l] / xa[1], delta=1e-3 * xa[l] / xa[1] + 1e-9)

    def test_anisotropic_spacing_from_the_header(self):
        nii = sv.nifti_bytes(self.labels, spacing=(1.0, 1.0, 2.0))
        r, body = self.describe(nii, "?labels=2")
        self.assertEqual(r.status, 200, body)
        self.assertEqual(body["volume"]["spacing"], [1.0, 1.0, 2.0])
        o = body["objects"][0]["object"]
        self.assertAlmostEqual(o["surface"]["voxel_volume"], 2.0 * self.counts[2], delta=1e-9)
        self.assertAlmostEqual(o["centroid"][2], 2 * 14, delta=0.1)

    def test_classify_predicts_every_described_object(self):
        if self.models is None:
            self.skipTest("no default model")
        r = self.server.post_mesh("/v1/classify?labels=1,2,5", self.nii)
        body = r.json()
        self.assertEqual(r.status, 207, body)  # 5 is the lattice
        h.validate("VolumeResult", body)
        objects = by_label(body)
        for label in (1, 2):
            self.assertIn("prediction", objects[label]["result"])
            self.assertEqual(objects[label]["result"]["descriptor"]["settings"]["source"], "model")
        self.assertEqual(objects[5]["error"]["code"], "genus_nonzero")
        self.assertIn("name", body["model"])

    def test_multipart_mixes_volumes_and_meshes(self):
        with open(SPHERE_OFF, "rb") as f:
            sphere = f.read()
        r = self.server.post_multipart("/v1/describe", [("mesh", "cells.nii", self.nii), ("mesh2", "sphere.off", sphere)],
                                       fields={"labels": "2"})
        body = r.json()
        # A volume parameter with a mesh part is refused for that part, not ignored: the parts differ, 207.
        self.assertEqual(r.status, 207, body)
        h.validate("BatchResponse", body)
        vol, mesh = body["results"]
        self.assertEqual(vol["status"], 200)
        self.assertEqual(vol["result"]["volume"]["filename"], "cells.nii")
        self.assertEqual([o["label_id"] for o in vol["result"]["objects"]], [2])
        self.assertEqual(mesh["status"], 400)
        self.assertEqual(mesh["error"]["details"]["parameter"], "labels")
        r = self.server.post_multipart("/v1/describe", [("mesh", "cells.nii", self.nii), ("mesh2", "sphere.off", sphere)])
        # The whole scene: its objects differ (the lattice is refused), so the volume part is 207 itself.
        self.assertEqual([x["status"] for x in r.json()["results"]], [207, 200])
        self.assertEqual(r.status, 207)

    def test_bad_volume_parameters(self):
        for query, parameter in (("?spacing=1,2", "spacing"), ("?spacing=1,0,1", "spacing"), ("?labels=a", "labels"),
                                 ("?labels=0", "labels"), ("?min_voxels=-1", "min_voxels"),
                                 ("?drop_truncated=maybe", "drop_truncated"), ("?objects=cells", "objects"),
                                 ("?unit=n%20m", "unit")):
            r, body = self.describe(self.nii, query)
            self.assertEqual(r.status, 400, query)
            self.assertEqual(body["error"]["code"], "invalid_parameter", query)
            self.assertEqual(body["error"]["details"]["parameter"], parameter, query)

    def test_soft_edged_mask_is_thresholded_and_says_so(self):
        n = 28
        soft = sv.soft_ball(n)
        nii = sv.nifti_bytes(soft, dims=(n, n, n))
        r, body = self.describe(nii, "?lmax=4&method=cmcf")
        self.assertEqual(r.status, 200, body)
        h.validate("VolumeResult", body)
        decision = body["volume"]["input"]
        self.assertEqual((decision["kind"], decision["threshold"], decision["warnings"]), ("soft_mask", 127.5, []))
        self.assertIn("interpolated edges", decision["why"])
        self.assertEqual(len(body["objects"]), 1)  # not one object per grey level
        self.assertEqual(body["objects"][0]["object"]["voxel_count"], sum(1 for v in soft if v >= 127.5))
        # ?threshold= sets it, in the file's values.
        r, body = self.describe(nii, "?lmax=4&method=cmcf&threshold=250")
        self.assertEqual(r.status, 200, body)
        self.assertEqual(body["volume"]["input"]["threshold"], 250)
        self.assertIn("set by the caller", body["volume"]["input"]["why"])
        self.assertEqual(body["objects"][0]["object"]["voxel_count"], sum(1 for v in soft if v >= 250))
        for query in ("?threshold=0", "?threshold=abc", "?objects=labels&threshold=100"):
            r, body = self.describe(nii, query)
            self.assertEqual(r.status, 400, query)
            self.assertEqual(body["error"]["code"], "invalid_parameter", query)
            self.assertEqual(body["error"]["details"]["parameter"], "threshold", query)
        # Read as labels, each grey level is an object, and the answer warns with the option that helps.
        r, body = self.describe(nii, "?lmax=4&method=cmcf&objects=labels&labels=255")
        h.validate("VolumeResult", body)
        self.assertEqual(body["volume"]["input"]["kind"], "soft_mask")
        self.assertGreater(body["volume"]["objects_found"], 15)
        self.assertEqual(len(body["volume"]["input"]["warnings"]), 1)
        self.assertIn("objects=components&threshold=T", body["volume"]["input"]["warnings"][0])

    def test_broken_volume_is_a_parse_error(self):
        r, body = self.describe(self.nii[:400])  # header and a few voxels
        self.assertGreaterEqual(r.status, 400)
        self.assertLess(r.status, 500)
        self.assertEqual(body["error"]["code"], "parse_error", body)


@unittest.skipIf(SKIP, SKIP or "")
class ServerVolumeLimitsTest(unittest.TestCase):
    def setUp(self):
        self.labels, self.counts = sv.ellipsoid_scene()
        self.nii = sv.nifti_bytes(self.labels)

    def test_voxel_limit(self):
        with h.Server(args=["--max-volume-voxels", "10000"]) as s:
            r = s.post_mesh("/v1/describe", self.nii)
            body = r.json()
            self.assertEqual(r.status, 413, body)
            self.assertEqual(body["error"]["code"], "limit_exceeded")
            self.assertEqual(body["error"]["details"]["allowed"], 10000)
            self.assertEqual(body["error"]["details"]["value"], sv.DIMS[0] * sv.DIMS[1] * sv.DIMS[2])

    def test_object_limit(self):
        with h.Server(args=["--max-volume-objects", "3"]) as s:
            r = s.post_mesh("/v1/describe", self.nii)
            body = r.json()
            self.assertEqual(r.status, 413, body)
            self.assertEqual(body["error"]["code"], "limit_exceeded")
            # Counted before the filters: a label subset does not get round the limit.
            self.assertEqual(s.post_mesh("/v1/describe?labels=1", self.nii).status, 413)

    def test_volume_time_limit_is_its_own(self):
        with open(SPHERE_OFF, "rb") as f:
            sphere = f.read()
        with h.Server(args=["--volume-time-limit", "0.001", "--time-limit", "60"]) as s:
            r = s.post_mesh("/v1/describe", self.nii)
            body = r.json()
            self.assertEqual(r.status, 504, body)
            self.assertEqual(body["error"]["code"], "timeout")
            self.assertEqual(s.post_mesh("/v1/describe", sphere).status, 200)  # meshes keep the request time limit


if __name__ == "__main__":
    unittest.main()
