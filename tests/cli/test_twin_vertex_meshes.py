"""The default CLI paths on meshes with a twin vertex (issue 24 item 1): one vertex duplicated at exactly the same
position plus the two zero-area faces that the twin makes — the defect of real dendritic-spine segmentations. The
default repairs weld the twin and collapse its zero-length edge (repair "collapsed_zero_length_edges"); before that
repair, welding left two faces repeating a vertex and validation refused the mesh ("degenerate_faces").

Every command runs with its default options (no repair is turned off). The meshes are made here
(tests/testing/twin_vertex_mesh.py); nmv_spine_5 and nmv_spine_23 of ../shared/data/hard/nmv_spines carry the
defect in real data and are run when present. Environment (set by ctest): WISH_BIN, WISH_SHARED_DATA.
"""
import csv
import io
import json
import os
import shutil
import tempfile
import unittest

from wish_cli import WISH_BIN, run  # tests/testing

import twin_vertex_mesh as twin

SOURCE_DIR = os.environ.get("WISH_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
SHARED_DATA = os.environ.get("WISH_SHARED_DATA", os.path.join(SOURCE_DIR, "..", "shared", "data"))
NMV_SPINES = os.path.join(SHARED_DATA, "hard", "nmv_spines")



def write(path, data):
    with open(path, "wb") as f:
        f.write(data)
    return path


@unittest.skipUnless(os.path.exists(WISH_BIN), "wish binary not found at %s (set WISH_BIN)" % WISH_BIN)
class TwinVertexCliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="wish-twin-")
        cls.clean_v, cls.clean_f = twin.ellipsoid_mesh(1.0, 0.7, 0.5, 3)
        v, f = twin.split_vertex(cls.clean_v, cls.clean_f, 5)
        assert twin.zero_area_faces(v, f) == 2 and len(v) == len(cls.clean_v) + 1  # the defect is there
        cls.clean = write(os.path.join(cls.dir, "clean.off"), twin.off_bytes(cls.clean_v, cls.clean_f))
        cls.twin = write(os.path.join(cls.dir, "twin.off"), twin.off_bytes(v, f))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_inspect_lists_the_weld_and_the_collapse(self):
        row = json.loads(run("inspect", self.twin, "--json").stdout)[0]
        self.assertTrue(row["valid"], row["issues"])
        repairs = {r["code"]: r["count"] for r in row["mesh"]["repairs"]}
        self.assertEqual(repairs, {"welded_duplicate_vertices": 1, "collapsed_zero_length_edges": 1})
        self.assertEqual(row["mesh"]["prepared"]["vertices"], len(self.clean_v))
        self.assertEqual(row["mesh"]["prepared"]["faces"], len(self.clean_f))

    def test_describe_keeps_the_mesh_and_gives_the_clean_mesh_descriptor(self):
        # The collapse gives back exactly the clean mesh (the twin welds into vertex 5; the two zero-area faces were
        # appended last), so the descriptor is the clean mesh's, number for number.
        rows = json.loads(run("describe", self.twin, self.clean, "--json", "--quiet").stdout)
        self.assertEqual(len(rows), 2)
        for row in rows:
            self.assertNotIn("error", row)
            self.assertEqual((row["n_vertices"], row["n_faces"]), (len(self.clean_v), len(self.clean_f)))
            self.assertEqual(row["map"]["flipped_faces"], 0)
        self.assertEqual(rows[0]["descriptor"], rows[1]["descriptor"])

    def test_train_on_class_folders_of_twin_vertex_meshes_keeps_every_mesh(self):
        data = os.path.join(self.dir, "classes")
        shapes = {"round": [(1.0, 0.95 - 0.02 * k, 0.9 + 0.02 * k) for k in range(6)],
                  "long": [(2.0 + 0.1 * k, 0.8, 0.6 - 0.02 * k) for k in range(6)]}
        for cls, axes in shapes.items():
            os.makedirs(os.path.join(data, cls))
            for k, (a, b, c) in enumerate(axes):
                v, f = twin.split_vertex(*twin.ellipsoid_mesh(a, b, c, 3), 7 + 11 * k)  # a different twin each
                write(os.path.join(data, cls, "%s%d.off" % (cls, k)), twin.off_bytes(v, f))
        model = os.path.join(self.dir, "model.json")
        report = os.path.join(self.dir, "report.json")
        desc = os.path.join(self.dir, "desc.csv")
        # Default recipe and repairs; only the grid search is kept small.
        run("train", data, "--out", model, "--report", report, "--save-descriptors", desc, "--jobs", "1",
            "--nested-repeats", "0", "--grid-splits", "2", "--no-compare", "--quiet")
        with open(report) as f:
            self.assertEqual(json.load(f)["skipped"], [])
        with open(desc) as f:
            rows = list(csv.DictReader(io.StringIO(f.read())))
        self.assertEqual(len(rows), 12)  # every mesh kept (before the repair: every one refused, degenerate_faces)
        p = run("predict", "--model", model, os.path.join(data, "long", "long3.off"), "--json", "--quiet")
        self.assertEqual(json.loads(p.stdout)["predictions"][0]["label"], "long")

    def test_shared_nmv_spines_with_a_twin_vertex_are_described(self):
        files = [os.path.join(NMV_SPINES, "nmv_spine_%d.obj" % k) for k in (5, 23)]
        if not all(os.path.exists(f) for f in files):
            self.skipTest("shared data not found at %s (set WISH_SHARED_DATA)" % NMV_SPINES)
        for row in json.loads(run("inspect", *files, "--json").stdout):
            self.assertTrue(row["valid"], row["issues"])
            self.assertIn("collapsed_zero_length_edges", [r["code"] for r in row["mesh"]["repairs"]])
        rows = json.loads(run("describe", *files, "--json", "--quiet", check=False).stdout)
        for row in rows:
            self.assertNotIn("error", row, row.get("error"))
            self.assertEqual(row["map"]["flipped_faces"], 0)


if __name__ == "__main__":
    unittest.main()
