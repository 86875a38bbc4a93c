"""/v1/classify and /v1/describe over HTTP on a mesh with a twin vertex (issue 24 item 1): one vertex duplicated at
exactly the same position plus the two zero-area faces that the twin makes (real spine segmentations). The default
repairs weld the twin and collapse its zero-length edge, list both in mesh.repairs, and the answer is the clean
mesh's; before that repair the service refused such a mesh with 422 degenerate_faces. Default query, default model.
"""
import os
import shutil
import tempfile
import unittest

import twin_vertex_mesh as twin
import wish_server_harness as h

SKIP = h.skip_reason_binary()


@unittest.skipIf(SKIP, SKIP or "")
class ServerTwinVertexTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-twin-http-")
        cls.models = h.models_dir_with_default(cls.tmp)
        cls.server = h.Server(models_dir=cls.models, args=["--workers", "1", "--queue-size", "4"])
        v, f = twin.ellipsoid_mesh(1.6, 0.8, 0.6, 3)
        cls.clean_off = twin.off_bytes(v, f)
        tv, tf = twin.split_vertex(v, f, 9)
        assert twin.zero_area_faces(tv, tf) == 2  # the defect is there
        cls.twin_off = twin.off_bytes(tv, tf)
        cls.vertices, cls.faces = len(v), len(f)

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def check_repaired(self, body):
        repairs = {r["code"]: r["count"] for r in body["mesh"]["repairs"]}
        self.assertEqual(repairs, {"welded_duplicate_vertices": 1, "collapsed_zero_length_edges": 1})
        self.assertEqual((body["mesh"]["prepared"]["vertices"], body["mesh"]["prepared"]["faces"]), (self.vertices, self.faces))
        self.assertEqual(body["map"]["quality"]["flipped_faces"], 0)

    def test_classify_keeps_a_twin_vertex_mesh_and_answers_as_for_the_clean_mesh(self):
        if self.models is None:
            self.skipTest("no default model at %s" % h.DEFAULT_MODEL)
        r = self.server.post_mesh("/v1/classify", self.twin_off, "application/off")
        self.assertEqual(r.status, 200, r.body[:500])
        body = r.json()
        h.validate("ClassifyResult", body)
        self.check_repaired(body)
        clean = self.server.post_mesh("/v1/classify", self.clean_off, "application/off")
        self.assertEqual(clean.status, 200, clean.body[:500])
        self.assertEqual(body["prediction"]["label"], clean.json()["prediction"]["label"])
        self.assertEqual(body["descriptor"], clean.json()["descriptor"])  # the collapse gives back the clean mesh

    def test_describe_keeps_a_twin_vertex_mesh(self):
        r = self.server.post_mesh("/v1/describe", self.twin_off, "application/off")
        self.assertEqual(r.status, 200, r.body[:500])
        body = r.json()
        h.validate("DescribeResult", body)
        self.check_repaired(body)


if __name__ == "__main__":
    unittest.main()
