"""`wish describe`, `wish predict` and `wish train` on label volumes (issue 13): one result per object, keyed by
label id; errors per object, never an object lost silently.

The volumes are made in the test: small NIfTI-1 files (written here with struct, uncompressed and gzipped) holding
voxelised ellipsoids (genus 0: described) and a lattice of bars (genus 81: its handle repair would change 19 % of
its voxels, over the default bound of 10 %, so it is refused with its reason), at anisotropic spacing. A torus is
repaired by default (its tube cut): test_a_torus_is_repaired_by_default_and_refused_without_repair.
Environment (set by ctest): WISH_BIN, the wish executable.
"""
import csv
import gzip
import io
import json
import os
import shutil
import sys
import tempfile
import unittest

from wish_cli import WISH_BIN, read_text, run  # tests/testing

import synthetic_volume

SOURCE_DIR = os.environ.get("WISH_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))


def nifti_bytes(dims, labels, spacing=(1.0, 1.0, 1.0)):
    """NIfTI-1 single file, uint8 voxels, x fastest (tests/testing/synthetic_volume.py). labels: {(x, y, z): value}."""
    nx, ny, nz = dims
    data = bytearray(nx * ny * nz)
    for (x, y, z), v in labels.items():
        data[x + nx * (y + ny * z)] = v
    return synthetic_volume.nifti_bytes(data, dims=dims, spacing=spacing)


def ellipsoid(center, axes, spacing):
    """Voxels (indices) whose centre, in physical units, is inside the ellipsoid."""
    cx, cy, cz = center
    a, b, c = axes
    out = []
    r = [int(max(axes) / min(spacing)) + 2] * 3
    for z in range(int(cz / spacing[2]) - r[2], int(cz / spacing[2]) + r[2] + 1):
        for y in range(int(cy / spacing[1]) - r[1], int(cy / spacing[1]) + r[1] + 1):
            for x in range(int(cx / spacing[0]) - r[0], int(cx / spacing[0]) + r[0] + 1):
                px, py, pz = x * spacing[0], y * spacing[1], z * spacing[2]
                if ((px - cx) / a) ** 2 + ((py - cy) / b) ** 2 + ((pz - cz) / c) ** 2 <= 1:
                    out.append((x, y, z))
    return out


def torus(center, R, r, spacing):
    cx, cy, cz = center
    out = []
    n = int((R + r) / min(spacing)) + 2
    for z in range(int(cz / spacing[2]) - n, int(cz / spacing[2]) + n + 1):
        for y in range(int(cy / spacing[1]) - n, int(cy / spacing[1]) + n + 1):
            for x in range(int(cx / spacing[0]) - n, int(cx / spacing[0]) + n + 1):
                px, py, pz = x * spacing[0], y * spacing[1], z * spacing[2]
                q = ((px - cx) ** 2 + (py - cy) ** 2) ** 0.5 - R
                if q * q + (pz - cz) ** 2 <= r * r:
                    out.append((x, y, z))
    return out


def lattice(lo=(26, 5, 2)):
    """A 4 x 4 x 4 lattice of 2 x 2-voxel bars 4 voxels apart from voxel `lo` (synthetic_volume.in_lattice)."""
    return [(x, y, z) for z in range(lo[2], lo[2] + 14) for y in range(lo[1], lo[1] + 14) for x in range(lo[0], lo[0] + 14)
            if synthetic_volume.in_lattice(x, y, z, lo=lo)]


SPACING = (1.0, 1.0, 1.5)  # anisotropic, like most microscopy


def volume(objects, dims=(64, 24, 18)):
    """objects: [(label, voxels)] -> NIfTI bytes."""
    labels = {}
    for value, voxels in objects:
        for v in voxels:
            labels[v] = value
    return nifti_bytes(dims, labels, SPACING)


def round_volume(shift):
    """Three nearly round blobs (labels 2, 5, 9 — ids need not be consecutive)."""
    return volume([(2, ellipsoid((10, 12, 13), (5.5 + shift, 5.0, 5.0), SPACING)),
                   (5, ellipsoid((31, 12, 13), (5.0, 5.5 - shift, 5.0), SPACING)),
                   (9, ellipsoid((52, 12, 13), (5.2, 5.2, 4.8 + shift), SPACING))])


def long_volume(shift):
    """Three elongated ellipsoids (labels 1, 2, 3)."""
    return volume([(1, ellipsoid((10, 12, 13), (8.0 + shift, 3.5, 3.5), SPACING)),
                   (2, ellipsoid((31, 12, 13), (8.5, 3.5 - shift / 2, 3.5), SPACING)),
                   (3, ellipsoid((52, 12, 13), (8.0 - shift, 3.5, 3.8), SPACING))])




class VolumeInputs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="wish_volume_cli_")
        # Two ellipsoids (labels 3 and 7) and a lattice (label 4): two results, one refusal with its genus.
        cls.mixed = os.path.join(cls.dir, "mixed.nii")
        with open(cls.mixed, "wb") as f:
            f.write(volume([(3, ellipsoid((12, 12, 13), (6.0, 5.0, 4.5), SPACING)),
                            (4, lattice()),
                            (7, ellipsoid((52, 12, 13), (8.0, 4.0, 4.0), SPACING))]))
        # Content, not the name, decides: a gzipped copy with a misleading name.
        cls.gz = os.path.join(cls.dir, "mixed-copy.dat")
        with open(cls.mixed, "rb") as f, open(cls.gz, "wb") as g:
            g.write(gzip.compress(f.read()))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_describe_json_one_row_per_object_keyed_by_label_id(self):
        p = run("describe", self.mixed, "--json", "--lmax", "6", "--method", "cmcf", "--quiet", check=False)
        self.assertEqual(p.returncode, 1, p.stderr)  # the lattice was refused
        rows = json.loads(p.stdout)
        self.assertEqual([r["label_id"] for r in rows], [3, 4, 7])
        by = {r["label_id"]: r for r in rows}
        for lid in (3, 7):
            self.assertNotIn("error", by[lid])
            self.assertEqual(len(by[lid]["descriptor"]["invariants"]), 7)
            self.assertEqual(by[lid]["object"]["genus"], 0)
            self.assertFalse(by[lid]["object"]["truncated"])
            self.assertEqual(by[lid]["file"], self.mixed)
        self.assertEqual(by[4]["error"]["code"], "genus_nonzero")
        self.assertEqual(by[4]["object"]["genus"], 81)
        self.assertFalse(by[4]["object"]["topology"]["repaired"])
        self.assertGreater(by[4]["object"]["topology"]["repair"]["volume_change"], 0.1)
        # The object block is in physical units: the voxel volume is voxels x 1.5.
        o = by[3]["object"]
        self.assertAlmostEqual(o["surface"]["voxel_volume"] / o["voxel_count"], 1.5, delta=0.15)
        # The elongated object (label 7) has more energy above l = 1 relative to xi(1) than the rounder one.
        xi3, xi7 = by[3]["descriptor"]["invariants"], by[7]["descriptor"]["invariants"]
        self.assertGreater(xi7[2] / xi7[1], xi3[2] / xi3[1])

    def test_describe_csv_has_label_id_column_and_errors_on_stderr(self):
        p = run("describe", self.gz, "--csv", "--lmax", "4", "--method", "cmcf", "--quiet", check=False)
        self.assertEqual(p.returncode, 1)
        rows = list(csv.DictReader(io.StringIO(p.stdout)))
        self.assertEqual([r["label_id"] for r in rows], ["3", "7"])
        self.assertTrue(all(r["file"] == self.gz for r in rows))
        self.assertIn(self.gz + "#4: error [genus_nonzero]", p.stderr)
        # Filters: only label 7 asked for -> one row, exit 0.
        p = run("describe", self.gz, "--csv", "--lmax", "4", "--method", "cmcf", "--quiet", "--label-ids", "7")
        self.assertEqual([r["label_id"] for r in csv.DictReader(io.StringIO(p.stdout))], ["7"])

    def test_describe_meshes_keep_an_empty_label_id(self):
        mesh = os.path.join(self.dir, "tetra.off")
        with open(mesh, "w") as f:  # too coarse to map well, but read: we only check the row layout
            f.write("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
        p = run("describe", mesh, self.mixed, "--json", "--lmax", "4", "--method", "cmcf", "--quiet", check=False)
        rows = json.loads(p.stdout)
        self.assertEqual(rows[0]["file"], mesh)
        self.assertNotIn("label_id", rows[0])
        self.assertEqual([r.get("label_id") for r in rows[1:]], [3, 4, 7])

    def test_an_object_over_the_box_limit_is_too_large_as_in_the_service(self):
        # One owner of a volume object (core/pipeline/volume_description.hpp): a refused surface takes the category
        # its code has in the code table, in every front end. Before, the CLI made every refusal `unmappable` while
        # the service answered box_too_large with 413. The same volume and limit through the CLI and the service:
        # the same code per object, the CLI's category too_large, the service's status 413 (its category's status).
        p = run("describe", self.mixed, "--json", "--lmax", "4", "--quiet", "--max-object-box-voxels", "100",
                check=False)
        self.assertEqual(p.returncode, 1, p.stderr)
        rows = {r["label_id"]: r for r in json.loads(p.stdout)}
        self.assertEqual(sorted(rows), [3, 4, 7])
        for r in rows.values():
            self.assertEqual(r["error"]["code"], "box_too_large")
            self.assertEqual(r["error"]["category"], "too_large")
            self.assertEqual(r["error"]["details"]["label_id"], r["label_id"])
            self.assertIn("voxel_count", r["object"])  # the object block is reported with its refusal
        # A shape refusal keeps its own category: without the limit the lattice is unmappable (the service's 422).
        p = run("describe", self.mixed, "--json", "--lmax", "4", "--quiet", "--label-ids", "4", check=False)
        torus = json.loads(p.stdout)[0]
        self.assertEqual((torus["error"]["code"], torus["error"]["category"]), ("genus_nonzero", "unmappable"))

        sys.path.insert(0, os.path.join(SOURCE_DIR, "tests", "server"))
        import wish_server_harness as h  # noqa: E402 (needs jsonschema, as every service test)
        with open(self.mixed, "rb") as f:
            data = f.read()
        with h.Server(args=["--max-object-box-voxels", "100"]) as s:
            r = s.post_mesh("/v1/describe?lmax=4", data)
            body = r.json()
        self.assertEqual(r.status, 413, r.body[:400])
        h.validate("VolumeResult", body)
        served = {o["label_id"]: o for o in body["objects"]}
        self.assertEqual(sorted(served), sorted(rows))
        for lid, o in served.items():
            self.assertEqual((o["status"], o["error"]["code"]), (413, rows[lid]["error"]["code"]))
            # One encoder of the object block: the CLI's row carries the service's block, key for key.
            self.assertEqual(set(o["object"]), set(rows[lid]["object"]))
            self.assertEqual(o["object"]["bbox_min"], rows[lid]["object"]["bbox_min"])

    def test_mesh_labels_reports_each_object_as_describe_does(self):
        # mesh-labels renders the same object (core/pipeline/volume_description.hpp): meshed objects are written,
        # a refused one is a row with its code, and the box limit refuses with box_too_large as describe does.
        out = os.path.join(self.dir, "meshes")
        p = run("mesh-labels", self.mixed, "--out", out, "--quiet", check=False)
        self.assertEqual(p.returncode, 1, p.stderr)  # the lattice is refused
        with open(os.path.join(out, "objects.csv")) as f:
            rows = {int(r["label_id"]): r for r in csv.DictReader(f)}
        self.assertEqual(sorted(rows), [3, 4, 7])
        for lid in (3, 7):
            self.assertEqual(rows[lid]["status"], "meshed")
            self.assertTrue(os.path.exists(os.path.join(out, rows[lid]["file"])))
            self.assertGreater(int(rows[lid]["vertices"]), 0)
            self.assertEqual(rows[lid]["unit"], "mm")  # the NIfTI default unit: the object's figures are in it
        self.assertEqual((rows[4]["status"], rows[4]["file"]), ("refused", ""))
        self.assertTrue(rows[4]["reason"].startswith("genus_nonzero: "), rows[4]["reason"])
        out = os.path.join(self.dir, "meshes-box")
        run("mesh-labels", self.mixed, "--out", out, "--quiet", "--max-object-box-voxels", "100", check=False)
        with open(os.path.join(out, "objects.csv")) as f:
            reasons = [r["reason"].split(":")[0] for r in csv.DictReader(f)]
        self.assertEqual(reasons, ["box_too_large"] * 3)

    def test_a_torus_is_repaired_by_default_and_refused_without_repair(self):
        path = os.path.join(self.dir, "torus.nii")
        with open(path, "wb") as f:
            f.write(volume([(4, torus((32, 12, 13), 5.0, 2.2, SPACING))]))
        out = os.path.join(self.dir, "torus-default")
        run("mesh-labels", path, "--out", out, "--quiet")
        with open(os.path.join(out, "objects.csv")) as f:
            [row] = list(csv.DictReader(f))
        self.assertEqual((row["genus"], row["status"], row["repair"]), ("1", "meshed", "cut"))
        self.assertLess(float(row["volume_change"]), 0.1)
        self.assertIn("removed the handles: cut 1 handle (-", row["repairs"])
        out = os.path.join(self.dir, "torus-off")
        p = run("mesh-labels", path, "--out", out, "--quiet", "--no-close-handles", check=False)
        self.assertEqual(p.returncode, 1)
        with open(os.path.join(out, "objects.csv")) as f:
            [row] = list(csv.DictReader(f))
        self.assertEqual(row["status"], "refused")
        self.assertIn("handle repair is off", row["reason"])

    def test_unreadable_volume_is_one_error_row(self):
        bad = os.path.join(self.dir, "truncated.nii")
        with open(self.mixed, "rb") as f, open(bad, "wb") as g:
            g.write(f.read()[:2000])  # header intact, voxel data cut
        p = run("describe", bad, "--json", "--quiet", check=False)
        self.assertEqual(p.returncode, 1)
        rows = json.loads(p.stdout)
        self.assertEqual(len(rows), 1)
        self.assertNotIn("label_id", rows[0])
        self.assertIn("code", rows[0]["error"])

    def test_train_on_class_folders_of_volumes_then_predict_per_object(self):
        data = os.path.join(self.dir, "classes")
        for cls, make in (("round", round_volume), ("long", long_volume)):
            os.makedirs(os.path.join(data, cls), exist_ok=True)
            for k, shift in enumerate((0.0, 0.4, 0.8)):
                with open(os.path.join(data, cls, f"{cls}{k}.nii"), "wb") as f:
                    f.write(make(shift))
        with open(os.path.join(data, "round", "README.txt"), "w") as f:
            f.write("not an input")
        model = os.path.join(self.dir, "model.json")
        report = os.path.join(self.dir, "report.json")
        desc = os.path.join(self.dir, "desc.csv")
        # No recipe options: the defaults are the recipe chosen by accuracy (docs/accuracy.md), the bundled model's.
        run("train", data, "--out", model, "--report", report, "--save-descriptors", desc, "--jobs", "1",
            "--nested-repeats", "0", "--grid-splits", "2", "--no-compare", "--quiet")
        recipe = json.loads(read_text(model))["payload"]["recipe"]
        self.assertEqual(recipe["map"]["method"], "cmcf")
        self.assertEqual((recipe["features"]["l_max"], recipe["features"]["log"]), (10, True))
        default_model = os.path.join(SOURCE_DIR, "data", "models", "default.json")
        if os.path.exists(default_model):  # scripts/make-default-model.sh trains with the same recipe
            shipped = json.loads(read_text(default_model))["payload"]["recipe"]
            self.assertEqual(shipped["map"]["method"], recipe["map"]["method"])
            self.assertEqual(shipped["features"], recipe["features"])
            self.assertEqual(shipped["sh"], recipe["sh"])
        rows = list(csv.DictReader(io.StringIO(read_text(desc))))
        self.assertEqual(len(rows), 18)  # 2 classes x 3 volumes x 3 objects, each one sample
        ids = {r["file"]: r["label"] for r in rows}
        self.assertEqual(ids[os.path.join(data, "round", "round1.nii") + "#5"], "round")
        self.assertEqual(ids[os.path.join(data, "long", "long2.nii") + "#3"], "long")
        rep = json.loads(read_text(report))
        self.assertEqual(rep["skipped"], [])
        # Predict on a fresh volume of each class: one row per label id, the right class.
        for cls, make, ids_expected in (("round", round_volume, [2, 5, 9]), ("long", long_volume, [1, 2, 3])):
            vol = os.path.join(self.dir, f"fresh-{cls}.nii")
            with open(vol, "wb") as f:
                f.write(make(0.2))
            p = run("predict", "--model", model, vol, "--json", "--quiet")
            preds = json.loads(p.stdout)["predictions"]
            self.assertEqual([r["label_id"] for r in preds], ids_expected)
            self.assertEqual([r["label"] for r in preds], [cls] * 3, preds)
        # The lattice of the mixed volume is a per-object error row; the others are predicted.
        p = run("predict", "--model", model, self.mixed, "--csv", "--quiet", check=False)
        self.assertEqual(p.returncode, 1)
        got = {r["label_id"]: r["label"] for r in csv.DictReader(io.StringIO(p.stdout))}
        self.assertEqual(set(got), {"3", "7"})
        self.assertEqual(got["7"], "long")
        self.assertIn("#4: error [genus_nonzero]", p.stderr)

    def test_train_manifest_with_label_ids_counts_every_lost_object(self):
        vols = []
        for k, shift in enumerate((0.0, 0.3, 0.6)):
            path = os.path.join(self.dir, f"m-round{k}.nii")
            with open(path, "wb") as f:
                f.write(round_volume(shift))
            vols.append(("round", path, [2, 5, 9]))
            path = os.path.join(self.dir, f"m-long{k}.nii")
            with open(path, "wb") as f:
                f.write(long_volume(shift))
            vols.append(("long", path, [1, 2, 3]))
        manifest = os.path.join(self.dir, "manifest.csv")
        with open(manifest, "w") as f:
            f.write("path,label,label_id\n")
            for cls, path, ids in vols:
                for i in ids:
                    f.write(f"{os.path.basename(path)},{cls},{i}\n")
            f.write("mixed.nii,long,7\n")    # one object of a volume with others: only it
            f.write("mixed.nii,round,4\n")   # the lattice: lost, genus_nonzero
            f.write("mixed.nii,round,42\n")  # no such label: lost, label_not_kept
        report = os.path.join(self.dir, "manifest-report.json")
        desc = os.path.join(self.dir, "manifest-desc.csv")
        common = ["train", manifest, "--out", os.path.join(self.dir, "m.json"), "--method", "cmcf", "--lmax", "6",
                  "--jobs", "1", "--nested-repeats", "0", "--grid-splits", "2", "--no-compare", "--quiet"]
        # 2 of 11 'round' objects lost = 18 % > the default 10 %: training stops and says why.
        p = run(*common, check=False)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("training_losses", p.stderr)
        run(*common, "--allow-losses", "--report", report, "--save-descriptors", desc)
        rows = list(csv.DictReader(io.StringIO(read_text(desc))))
        self.assertEqual(len(rows), 19)  # 18 + mixed#7
        self.assertEqual({r["label"] for r in rows if r["file"].endswith("mixed.nii#7")}, {"long"})
        skipped = {s["file"].rsplit("/", 1)[-1]: s for s in json.loads(read_text(report))["skipped"]}
        self.assertEqual(set(skipped), {"mixed.nii#4", "mixed.nii#42"})
        self.assertEqual(skipped["mixed.nii#4"]["code"], "genus_nonzero")
        self.assertEqual(skipped["mixed.nii#4"]["label"], "round")
        self.assertEqual(skipped["mixed.nii#42"]["code"], "label_not_kept")
        losses = {c["label"]: c for c in json.loads(read_text(report))["losses"]}
        self.assertEqual((losses["round"]["meshes"], losses["round"]["kept"], losses["round"]["lost"]), (11, 9, 2))
        self.assertEqual((losses["long"]["meshes"], losses["long"]["kept"], losses["long"]["lost"]), (10, 10, 0))


if __name__ == "__main__":
    unittest.main()
