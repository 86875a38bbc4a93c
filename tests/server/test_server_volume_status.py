"""The status of a label volume answer follows its objects' as a batch's follows its parts' (proto/openapi.json,
VolumeResult; test_server_batch_status.py for batches): every object described is 200; every object refused alike is
that status (422 for a lattice whose handle repair exceeds the bound), with the VolumeResult still listing every object and the first refusal at the top
level; objects that differ are 207 Multi-Status; a volume with no object left to describe is 422 `no_objects`.
As a multipart part, a volume has that status itself, and the batch's status follows its parts' as before.

The volumes are made here from the ellipsoid scene (tests/testing/synthetic_volume.py): the scene itself (four
mappable objects and a lattice), the scene without its lattice, the lattice alone, and an all-background volume."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import synthetic_volume as sv
import wish_server_harness as h

SKIP = h.skip_reason_binary()
sys.path.insert(0, os.path.join(h.SOURCE_DIR, "clients", "python"))
from wish_client import DescribeResult, RetryPolicy, VolumeResult, WishClient, WishServerError  # noqa: E402

LATTICE = 5  # the scene's genus-81 object, refused by default (synthetic_volume.py)


def keep_only(labels, keep):
    """The scene with every voxel whose label is not in `keep` set to background."""
    table = bytes(v if v in keep else 0 for v in range(256))
    return labels.translate(table)


@unittest.skipIf(SKIP, SKIP or "")
class VolumeStatusTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-volume-status-")
        cls.server = h.Server(models_dir=h.models_dir_with_default(cls.tmp), args=["--workers", "2"])
        labels, counts = sv.ellipsoid_scene()
        cls.scene = sv.nifti_bytes(labels)                                                   # 200 x4, 422
        cls.good = sv.nifti_bytes(keep_only(labels, set(counts) - {LATTICE}))                  # all 200
        cls.lattice = sv.nifti_bytes(keep_only(labels, {LATTICE}))                               # all 422
        cls.empty = sv.nifti_bytes(bytes(len(labels)))                                       # no object
        cls.genus4 = h.read_bytes(h.shared("negative", "anchor.off"))                        # a 422 mesh
        cls.sphere = h.read_bytes(h.shared("genus0_closed", "sphere.off"))                   # a 200 mesh
        cls.found = len(counts)
        cls.paths = {}
        for name in ("scene", "lattice"):
            cls.paths[name] = os.path.join(cls.tmp, name + ".nii")
            with open(cls.paths[name], "wb") as f:
                f.write(getattr(cls, name))

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def raw(self, data, query="", op="describe"):
        r = self.server.post_mesh("/v1/" + op + query, data)
        body = r.json()
        self.assertIn(str(r.status), h.OPENAPI["paths"]["/v1/" + op]["post"]["responses"])  # documented
        self.assertEqual(body["request_id"], r.header("X-Request-Id"))
        return r, body

    def object_statuses(self, body):
        return [o["status"] for o in body["objects"]]

    def test_every_object_described_is_200(self):
        r, body = self.raw(self.good)
        self.assertEqual(r.status, 200, r.body[:400])
        h.validate("VolumeResult", body)
        self.assertEqual(self.object_statuses(body), [200] * (self.found - 1))
        self.assertNotIn("error", body)

    def test_every_object_refused_is_that_status_with_every_object(self):
        for op in ("describe", "classify"):
            r, body = self.raw(self.lattice, op=op)
            self.assertEqual(r.status, 422, r.body[:400])
            h.validate("VolumeResult", body)  # not a bare Error: the objects are still there to read
            # One label value: `objects=auto` reads it as a mask (component 1); the object is the lattice, genus 81.
            self.assertEqual([o["object"]["genus"] for o in body["objects"]], [81])
            self.assertEqual(self.object_statuses(body), [422])
            self.assertEqual(body["objects"][0]["error"]["code"], "genus_nonzero")
            self.assertEqual(body["error"], body["objects"][0]["error"])  # like every error answer
            self.assertEqual(body["counts"], {"objects": 1, "described": 0, "refused": 1})

    def test_objects_that_differ_are_207(self):
        r, body = self.raw(self.scene)
        self.assertEqual(r.status, 207, r.body[:400])
        h.validate("VolumeResult", body)
        self.assertEqual(self.object_statuses(body), [200] * (self.found - 1) + [422])
        self.assertNotIn("error", body)  # a 207 is not an error answer
        # The filters choose the objects the rule is taken over: the same volume, lattice only or without it.
        self.assertEqual(self.raw(self.scene, "?labels=%d" % LATTICE)[0].status, 422)
        self.assertEqual(self.raw(self.scene, "?labels=1,2")[0].status, 200)
        self.assertEqual(self.raw(self.scene, "?labels=1,%d" % LATTICE, op="classify")[0].status, 207)

    def test_an_object_past_the_box_limit_is_its_own_413(self):
        # A per-object limit takes its own status, not the 422 of a shape refusal: every object over the box limit
        # is 413 box_too_large (before, every object refusal was reported as 422), and the volume answer follows.
        with h.Server(models_dir=h.models_dir_with_default(self.tmp),
                      args=["--max-object-box-voxels", "100"]) as s:
            r = s.post_mesh("/v1/describe", self.good)
            body = r.json()
            self.assertEqual(r.status, 413, r.body[:400])
            h.validate("VolumeResult", body)
            self.assertEqual(self.object_statuses(body), [413] * (self.found - 1))
            self.assertEqual({o["error"]["code"] for o in body["objects"]}, {"box_too_large"})
            self.assertEqual(body["error"]["code"], "box_too_large")

    def test_no_object_left_is_a_422_error(self):
        # Filtered out: every object found is dropped by one of the filters, and the details count them.
        r, body = self.raw(self.scene, "?labels=1&min_voxels=1000000")
        self.assertEqual(r.status, 422, r.body[:400])
        h.validate("Error", body)
        self.assertEqual(body["error"]["code"], "no_objects")
        d = body["error"]["details"]
        self.assertEqual(d["objects_found"], self.found)
        self.assertEqual(d["not_selected"] + d["small"] + d["truncated"], self.found)
        self.assertGreaterEqual(d["not_selected"], self.found - 1)  # labels=1 leaves one, min_voxels takes it
        self.assertIn("min_voxels", body["error"]["message"])
        # Nothing there at all: background only.
        r, body = self.raw(self.empty, op="classify")
        self.assertEqual((r.status, body["error"]["code"]), (422, "no_objects"), r.body[:400])
        self.assertEqual(body["error"]["details"]["objects_found"], 0)
        self.assertIn("background", body["error"]["message"])

    def test_multipart_volume_part_has_its_volume_status(self):
        def batch(*parts):
            files = [("mesh", "%s%d.%s" % (name, i, "off" if name.endswith("mesh") else "nii"), data)
                     for i, (name, data) in enumerate(parts)]
            r = self.server.post_multipart("/v1/describe", files)
            body = r.json()
            h.validate("BatchResponse", body)
            self.assertIn(str(r.status), h.OPENAPI["paths"]["/v1/describe"]["post"]["responses"])
            return r.status, [item["status"] for item in body["results"]], body

        status, parts, body = batch(("good", self.good), ("mesh", self.sphere))
        self.assertEqual((status, parts), (200, [200, 200]))
        status, parts, body = batch(("lattice", self.lattice))
        self.assertEqual((status, parts), (422, [422]))
        item = body["results"][0]
        self.assertEqual(item["error"]["code"], "genus_nonzero")
        self.assertEqual(body["error"], item["error"])
        self.assertEqual(self.object_statuses(item["result"]), [422])  # the part keeps its objects
        status, parts, body = batch(("lattice", self.lattice), ("badmesh", self.genus4))
        self.assertEqual((status, parts), (422, [422, 422]))  # a volume refused and a mesh refused alike
        status, parts, body = batch(("scene", self.scene))
        self.assertEqual((status, parts), (207, [207]))
        self.assertNotIn("error", body["results"][0])
        self.assertEqual(self.object_statuses(body["results"][0]["result"]), [200] * (self.found - 1) + [422])
        status, parts, body = batch(("good", self.good), ("lattice", self.lattice))
        self.assertEqual((status, parts), (207, [200, 422]))
        status, parts, body = batch(("empty", self.empty))
        self.assertEqual((status, parts), (422, [422]))
        self.assertEqual(body["results"][0]["error"]["code"], "no_objects")
        self.assertNotIn("result", body["results"][0])  # failed whole: nothing to list

    @unittest.skipUnless(shutil.which("curl"), "needs curl")
    def test_curl_fail_sees_a_refused_volume(self):
        url = "http://127.0.0.1:%d/v1/describe" % self.server.port

        def curl(path):
            done = subprocess.run(["curl", "-sS", "-f", "-o", os.devnull, "-w", "%{http_code}", "--data-binary",
                                   "@" + path, "-H", "Content-Type: application/octet-stream", url],
                                  capture_output=True, text=True, timeout=120)
            return done.returncode, done.stdout

        self.assertEqual(curl(self.paths["lattice"]), (22, "422"))  # curl -f: exit 22 on HTTP >= 400
        self.assertEqual(curl(self.paths["scene"]), (0, "207"))

    def test_python_client_reads_objects_of_every_answer(self):
        retries = []
        client = WishClient("http://127.0.0.1:%d" % self.server.port, timeout=120,
                            retry=RetryPolicy(max_attempts=4, base_delay=0.01),
                            on_retry=lambda attempt, delay, err: retries.append(err))
        out = client.describe_volume(("lattice.nii", self.lattice))                          # HTTP 422
        self.assertEqual([(o.status, o.error.code) for o in out.objects], [(422, "genus_nonzero")])
        out = client.classify_volume(("scene.nii", self.scene))                          # HTTP 207
        self.assertEqual([o.ok for o in out.objects], [True] * (self.found - 1) + [False])
        with self.assertRaises(WishServerError) as cm:                                     # failed whole: raises
            client.describe_volume(("empty.nii", self.empty))
        self.assertEqual((cm.exception.status, cm.exception.code), (422, "no_objects"))
        self.assertEqual(retries, [])  # a refusal of the input is never sent again

    def test_python_client_describe_reads_volume_parts(self):
        # describe()/classify() take a volume as they take a mesh: alone it is sent as a volume upload, among
        # meshes as a multipart part; either way it comes back as a VolumeResult, refused objects included.
        client = WishClient("http://127.0.0.1:%d" % self.server.port, timeout=120)
        out = client.describe([("scene.nii", self.scene), ("sphere.off", self.sphere), ("lattice.nii", self.lattice)])
        self.assertIsInstance(out[0], VolumeResult)
        self.assertEqual([o.ok for o in out[0].objects], [True] * (self.found - 1) + [False])
        self.assertIsInstance(out[1], DescribeResult)
        self.assertIsInstance(out[2], VolumeResult)  # a part whose objects were all refused still lists them
        self.assertEqual([(o.status, o.error.code) for o in out[2].objects], [(422, "genus_nonzero")])
        alone = client.classify(("scene.nii", self.scene))
        self.assertIsInstance(alone, VolumeResult)
        self.assertEqual(len(alone.objects), self.found)
        self.assertTrue(all(o.result.label for o in alone.objects if o.ok))


if __name__ == "__main__":
    unittest.main()
