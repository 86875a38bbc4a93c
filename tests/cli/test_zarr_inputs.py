"""`wish mesh-labels`, `describe`, `predict` and `train` on OME-Zarr label images (issue 26 item 3), as a user runs
them: a store directory or its zip named on the command line (or in a class folder / manifest) must give exactly the
objects its NIfTI original gives (ids, voxel counts, bounding boxes, surfaces, and ξ).

The stores are written by Debian's python3-zarr (tests/testing/ome_zarr_writer.py: an independent writer) from small
synthetic volumes (tests/cli/test_volume_inputs.py's ellipsoids and lattice), one per chunk compressor (zlib, gzip,
zstd, blosc lz4, blosc zstd, none), in C and F order, big-endian, with size-1 t and c axes, and as a ZipStore zip; and,
when ../shared/data/urocell is present, from a UroCell mitochondria volume. Environment (set by ctest): WISH_BIN.
"""
import csv
import io
import json
import os
import shutil
import tempfile
import unittest

import numpy as np

import ome_zarr_writer
import synthetic_volume
from test_volume_inputs import SPACING, ellipsoid, lattice, long_volume, read_text, round_volume, run, volume

SHARED = os.environ.get("WISH_SHARED_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
CODECS = ("zlib", "gzip", "zstd", "blosc", "blosc-zstd", "none")
# What objects.csv says about an object that does not depend on the input's format.
OBJECT_COLUMNS = ("label_id", "voxel_count", "centroid_x", "centroid_y", "centroid_z", "bbox_min_x", "bbox_min_y",
                  "bbox_min_z", "bbox_max_x", "bbox_max_y", "bbox_max_z", "truncated", "genus", "status", "reason",
                  "vertices", "faces", "mesh_area", "mesh_volume", "voxel_volume", "unit")


def nifti_labels(path):
    """(labels z, y, x; spacing x, y, z; unit) of a NIfTI file, read with numpy (ome_zarr_writer.read_nifti)."""
    return ome_zarr_writer.read_nifti(path)


def objects_by_volume(csv_path):
    out = {}
    for row in csv.DictReader(io.StringIO(read_text(csv_path))):
        out.setdefault(row["volume"], []).append({k: row[k] for k in OBJECT_COLUMNS})
    return out


def xi_by_label(stdout):
    return {r["label_id"]: r["descriptor"]["invariants"] for r in json.loads(stdout) if "descriptor" in r}


class ZarrInputs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="wish_zarr_cli_")
        cls.nifti = os.path.join(cls.dir, "mixed.nii")
        with open(cls.nifti, "wb") as f:
            f.write(volume([(3, ellipsoid((12, 12, 13), (6.0, 5.0, 4.5), SPACING)),
                            (4, lattice()),
                            (7, ellipsoid((52, 12, 13), (8.0, 4.0, 4.0), SPACING))]))
        cls.labels, cls.spacing, cls.unit = nifti_labels(cls.nifti)
        cls.stores = {}
        for codec in CODECS:
            path = os.path.join(cls.dir, f"mixed-{codec}.ome.zarr")
            ome_zarr_writer.write_store(path, cls.labels, spacing_xyz=cls.spacing, unit=cls.unit, codec=codec,
                                        chunks=(8, 10, 16))
            cls.stores[codec] = path
        variants = {
            "fortran": dict(order="F", codec="zstd"),
            "bigendian": dict(dtype=">u2", codec="blosc"),
            "int64": dict(dtype="<i8", codec="zlib"),
            "tc": dict(extra_axes=(("t", "time"), ("c", "channel")), codec="gzip"),
        }
        for name, kw in variants.items():
            path = os.path.join(cls.dir, f"mixed-{name}.zarr")
            ome_zarr_writer.write_store(path, cls.labels, spacing_xyz=cls.spacing, unit=cls.unit, chunks=(7, 9, 11),
                                        **kw)
            cls.stores[name] = path
        cls.zip = os.path.join(cls.dir, "mixed.zarr.zip")
        ome_zarr_writer.write_store(cls.zip, cls.labels, zip_store=True, spacing_xyz=cls.spacing, unit=cls.unit,
                                    codec="blosc", other_labels=("nuclei",))
        cls.stores["zip"] = cls.zip

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_mesh_labels_finds_the_nifti_objects_in_every_store(self):
        out = os.path.join(self.dir, "meshes")
        names = [n for n in self.stores if n != "zip"]
        p = run("mesh-labels", self.nifti, *[self.stores[n] for n in names], "--out", out, "--quiet", check=False)
        self.assertEqual(p.returncode, 1, p.stderr)  # the lattice (label 4) is refused in every copy
        by = objects_by_volume(os.path.join(out, "objects.csv"))
        expected = by["mixed"]
        self.assertEqual([r["label_id"] for r in expected], ["3", "4", "7"])
        self.assertEqual([r["status"] for r in expected], ["meshed", "refused", "meshed"])
        for n in names:
            stem = f"mixed-{n}"
            self.assertIn(stem, by, p.stderr)
            self.assertEqual(by[stem], expected, n)
        # The voxel counts are numpy's, not only the NIfTI path's.
        ids, counts = np.unique(self.labels[self.labels > 0], return_counts=True)
        self.assertEqual([(r["label_id"], r["voxel_count"]) for r in expected],
                         [(str(i), str(c)) for i, c in zip(ids.tolist(), counts.tolist())])

    def test_describe_gives_the_same_xi_from_the_zip_and_a_directory(self):
        common = ["--json", "--lmax", "6", "--method", "cmcf", "--quiet", "--label-ids", "3,7"]
        a = xi_by_label(run("describe", self.nifti, *common).stdout)
        self.assertEqual(sorted(a), [3, 7])
        for store, extra in ((self.zip, ["--label-image", "cells"]), (self.stores["fortran"], [])):
            b = xi_by_label(run("describe", store, *common, *extra).stdout)
            self.assertEqual(sorted(b), [3, 7], store)
            for lid in (3, 7):
                np.testing.assert_allclose(b[lid], a[lid], rtol=1e-9, atol=1e-12, err_msg=f"{store} #{lid}")

    def test_labels_and_level_choose_the_label_image(self):
        # The zip lists "nuclei" (2 x 2 x 2, empty) first: by default that is read, and it has no object.
        out = os.path.join(self.dir, "default-label-image")
        p = run("mesh-labels", self.zip, "--out", out)
        self.assertIn("2x2x2 uint8", p.stderr)
        self.assertEqual(objects_by_volume(os.path.join(out, "objects.csv")), {})
        # An unknown name is refused with the names the store has.
        p = run("mesh-labels", self.zip, "--label-image", "golgi", "--out", os.path.join(self.dir, "golgi"), "--quiet",
                check=False)
        self.assertEqual(p.returncode, 1)
        self.assertIn("no label image named 'golgi' (the store has: nuclei, cells)", p.stderr)
        # Level 1 is every second voxel at twice the voxel size: its objects are numpy's on labels[::2, ::2, ::2].
        out = os.path.join(self.dir, "level1")
        run("mesh-labels", self.stores["zlib"], "--level", "1", "--out", out, "--quiet", "--target-vertices", "0",
            check=False)
        rows = objects_by_volume(os.path.join(out, "objects.csv"))["mixed-zlib"]
        small = self.labels[::2, ::2, ::2]
        ids, counts = np.unique(small[small > 0], return_counts=True)
        self.assertEqual([(r["label_id"], r["voxel_count"]) for r in rows],
                         [(str(i), str(c)) for i, c in zip(ids.tolist(), counts.tolist())])
        # The level's voxel size (dataset scale x multiscale scale) is twice the full resolution's along each axis.
        r3 = rows[0]
        self.assertEqual(r3["label_id"], "3")
        self.assertAlmostEqual(float(r3["centroid_x"]) / (2 * SPACING[0]),
                               float(np.mean(np.nonzero(small == 3)[2])), places=4)
        self.assertAlmostEqual(float(r3["centroid_z"]) / (2 * SPACING[2]),
                               float(np.mean(np.nonzero(small == 3)[0])), places=4)

    def test_a_store_that_is_not_one_volume_is_refused_with_the_reason(self):
        import zarr
        path = os.path.join(self.dir, "two-channels.zarr")
        ome_zarr_writer.write_store(path, self.labels, extra_axes=(("c", "channel"),), codec="zlib")
        array = zarr.open(os.path.join(path, "labels", "cells", "0"), mode="r+")
        array.resize((2,) + self.labels.shape)  # a second channel: two label images in one array
        array[1] = self.labels
        p = run("mesh-labels", path, "--out", os.path.join(self.dir, "two"), "--quiet", check=False)
        self.assertEqual(p.returncode, 1)
        self.assertIn("axis 'c' has size 2", p.stderr)

    def test_train_on_class_folders_and_a_manifest_of_stores(self):
        data = os.path.join(self.dir, "classes")
        for cls, make in (("round", round_volume), ("long", long_volume)):
            os.makedirs(os.path.join(data, cls), exist_ok=True)
            for k, shift in enumerate((0.0, 0.4, 0.8)):
                nii = os.path.join(self.dir, f"{cls}{k}.nii")
                with open(nii, "wb") as f:
                    f.write(make(shift))
                labels, spacing, unit = nifti_labels(nii)
                # Two store directories and one zip per class; the codec varies too.
                zipped = k == 2
                name = f"{cls}{k}.zarr.zip" if zipped else f"{cls}{k}.ome.zarr"
                ome_zarr_writer.write_store(os.path.join(data, cls, name), labels, zip_store=zipped,
                                            spacing_xyz=spacing, unit=unit, codec=CODECS[k])
        desc = os.path.join(self.dir, "desc.csv")
        run("train", data, "--out", os.path.join(self.dir, "model.json"), "--save-descriptors", desc, "--jobs", "1",
            "--nested-repeats", "0", "--grid-splits", "2", "--no-compare", "--quiet")
        rows = list(csv.DictReader(io.StringIO(read_text(desc))))
        self.assertEqual(len(rows), 18)  # 2 classes x 3 stores x 3 objects
        files = {r["file"]: r["label"] for r in rows}
        self.assertEqual(files[os.path.join(data, "round", "round1.ome.zarr") + "#5"], "round")
        self.assertEqual(files[os.path.join(data, "long", "long2.zarr.zip") + "#3"], "long")
        # Predict on a store: one row per label id, the right class.
        p = run("predict", "--model", os.path.join(self.dir, "model.json"),
                os.path.join(data, "long", "long0.ome.zarr"), "--json", "--quiet")
        preds = json.loads(p.stdout)["predictions"]
        self.assertEqual([r["label_id"] for r in preds], [1, 2, 3])
        # A manifest row may name a store (directory or zip), with label ids.
        manifest = os.path.join(self.dir, "manifest.csv")
        with open(manifest, "w") as f:
            f.write("path,label,label_id\n")
            for cls, ids in (("round", (2, 5, 9)), ("long", (1, 2, 3))):
                for k in range(3):
                    name = f"{cls}{k}.zarr.zip" if k == 2 else f"{cls}{k}.ome.zarr"
                    for i in ids:
                        f.write(f"classes/{cls}/{name},{cls},{i}\n")
        desc2 = os.path.join(self.dir, "desc2.csv")
        run("train", manifest, "--out", os.path.join(self.dir, "m2.json"), "--save-descriptors", desc2, "--jobs", "1",
            "--nested-repeats", "0", "--grid-splits", "2", "--no-compare", "--quiet")
        self.assertEqual(len(list(csv.DictReader(io.StringIO(read_text(desc2))))), 18)

    @unittest.skipUnless(os.path.isdir(os.path.join(SHARED, "urocell", "mito", "instance")), "urocell absent")
    def test_urocell_mitochondria_as_ome_zarr_give_the_nifti_objects(self):
        src = os.path.join(SHARED, "urocell", "mito", "instance", "fib1-1-0-3.nii.gz")
        labels, spacing, unit = nifti_labels(src)
        store = os.path.join(self.dir, "fib1-1-0-3-zarr.ome.zarr")
        ome_zarr_writer.write_store(store, labels, spacing_xyz=spacing, unit=unit, codec="blosc", chunks=(64, 64, 64))
        out = os.path.join(self.dir, "urocell")
        common = ["--out", out, "--quiet", "--min-voxels", "500", "--drop-truncated", "--spacing", "16,16,15",
                  "--unit", "nm"]
        run("mesh-labels", src, store, *common, check=False)
        by = objects_by_volume(os.path.join(out, "objects.csv"))
        self.assertGreaterEqual(len(by["fib1-1-0-3"]), 3)
        self.assertEqual(by["fib1-1-0-3-zarr"], by["fib1-1-0-3"])
        # xi of two objects, described from each.
        ids = ",".join(r["label_id"] for r in by["fib1-1-0-3"] if r["status"] == "meshed")
        ids = ",".join(ids.split(",")[:2])
        desc = ["--json", "--lmax", "6", "--method", "cmcf", "--quiet", "--label-ids", ids, "--spacing", "16,16,15"]
        a = xi_by_label(run("describe", src, *desc).stdout)
        b = xi_by_label(run("describe", store, *desc).stdout)
        self.assertEqual(len(a), 2)
        self.assertEqual(sorted(a), sorted(b))
        for lid in a:
            np.testing.assert_allclose(b[lid], a[lid], rtol=1e-9, atol=1e-12)


if __name__ == "__main__":
    unittest.main()
