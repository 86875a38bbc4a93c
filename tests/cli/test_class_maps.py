"""`wish predict VOLUME --out-labels OUT` (issue 39 items 2 and 4): the class map of a label volume in the input's own
format, read back by the tools labs use — Debian's python3-nibabel (NIfTI), python3-pil (TIFF), python3-zarr
(OME-Zarr) and python3-anndata (the .h5ad table) — never by WISH's own readers: every object's voxels must carry
the class value the JSON gives it, background and dropped specks 0, and the input's geometry must be kept.

The volume is the synthetic scene (tests/testing/synthetic_volume.py: four genus-0 objects, a lattice of genus 81
that is refused) plus a one-voxel label, a speck. With ../shared/data present, a UroCell endolysosome mask
(lyso/binary/fib1-3-3-0: three objects) is classified in all three formats and the three maps must agree.
Environment (set by ctest): WISH_BIN, WISH_SOURCE_DIR, WISH_SHARED_DATA.
"""
import csv
import json
import os
import shutil
import tempfile
import unittest

import numpy as np

from wish_cli import SOURCE_DIR, run  # tests/testing

import ome_zarr_writer
import synthetic_volume as sv

try:
    import nibabel
except ImportError:  # python3-nibabel (scripts/install-deps.sh --test)
    nibabel = None
try:
    import anndata
except ImportError:
    anndata = None
try:
    from PIL import Image, ImageSequence
except ImportError:
    Image = None
import jsonschema
import zarr

MODEL = os.path.join(SOURCE_DIR, "data", "models", "default.json")
SCHEMA = os.path.join(SOURCE_DIR, "proto", "ngff-image-label.schema.json")
SPECK = 9
SHARED = os.environ.get("WISH_SHARED_DATA", os.path.join(SOURCE_DIR, "..", "shared", "data"))


def scene_zyx():
    labels, _ = sv.ellipsoid_scene()
    nx, ny, nz = sv.DIMS
    zyx = np.frombuffer(labels, dtype=np.uint8).reshape(nz, ny, nx).copy()
    zyx[25, 30, 2] = SPECK  # alone, far from every object
    return zyx


def predict(path, out, *extra):
    p = run("predict", "--model", MODEL, path, "--out-labels", out, "--json", "--quiet", *extra, check=False)
    # The lattice is refused, so the run reports a failure; everything else is written.
    assert p.returncode in (0, 1), p.stderr
    return json.loads(p.stdout)


def class_values(doc):
    return {r["label_id"]: r["class_value"] for r in doc["predictions"]}


class ClassMaps(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="wish_class_maps_")
        cls.zyx = scene_zyx()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def check_values(self, doc, class_map_zyx, source_zyx):
        """Every kept object's voxels hold its JSON class value; everything else (background, specks) is 0."""
        values = class_values(doc)
        legend = {v["name"]: v["value"] for v in doc["class_map"]["values"]}
        self.assertEqual(class_map_zyx.shape, source_zyx.shape)
        self.assertEqual(class_map_zyx.dtype, np.uint8)
        for label, value in values.items():
            self.assertEqual(np.unique(class_map_zyx[source_zyx == label]).tolist(), [value], label)
        for r in doc["predictions"]:
            if "error" in r:
                self.assertEqual(r["class_value"], legend["refused"])
            elif r["novel"]:
                self.assertEqual(r["class_value"], legend["novel"])
            else:
                self.assertEqual(r["class_value"], legend[r["label"]])
        dropped = [o for v in doc["volumes"] for o in v["volume"]["dropped_objects"]]
        self.assertEqual([(o["label_id"], o["reason"]) for o in dropped], [(SPECK, "speck")])
        self.assertTrue((class_map_zyx[source_zyx == SPECK] == 0).all())
        self.assertTrue((class_map_zyx[source_zyx == 0] == 0).all())

    @unittest.skipIf(nibabel is None, "needs python3-nibabel")
    def test_nifti_class_map_keeps_the_affine_and_is_read_by_nibabel(self):
        # A NIfTI with a rotated, shifted affine (qform and sform), written by nibabel.
        affine = np.array([[0, -0.5, 0, 12.5], [0.5, 0, 0, -3.0], [0, 0, 1.5, 40.25], [0, 0, 0, 1]])
        src = nibabel.Nifti1Image(np.transpose(self.zyx, (2, 1, 0)), affine)
        src.header.set_xyzt_units("mm")
        path = os.path.join(self.dir, "scene.nii.gz")
        nibabel.save(src, path)
        out = os.path.join(self.dir, "scene_classes.nii.gz")
        doc = predict(path, out)
        img = nibabel.load(out)
        np.testing.assert_allclose(img.affine, nibabel.load(path).affine, atol=1e-6)
        self.assertEqual(img.header.get_xyzt_units()[0], "mm")
        self.assertEqual(int(img.header["intent_code"]), 1002)  # NIFTI_INTENT_LABEL
        cm = np.transpose(np.asarray(img.dataobj), (2, 1, 0))
        self.check_values(doc, cm, self.zyx)

    @unittest.skipIf(Image is None, "needs python3-pil")
    def test_tiff_class_map_is_a_palette_stack_read_by_pil(self):
        # The input stack written by PIL, with ImageJ metadata for the voxel size.
        path = os.path.join(self.dir, "scene.tif")
        pages = [Image.fromarray(page) for page in self.zyx]
        info = {270: "ImageJ=1.11a\nimages=%d\nslices=%d\nunit=micron\nspacing=1.5\n" % (len(pages), len(pages))}
        pages[0].save(path, save_all=True, append_images=pages[1:], tiffinfo=info, resolution=2.0)
        out = os.path.join(self.dir, "scene_classes.tif")
        doc = predict(path, out)
        with Image.open(out) as im:
            cm = np.stack([np.array(f) for f in ImageSequence.Iterator(im)])
            im.seek(0)
            mode, palette, tags = im.mode, im.getpalette(), dict(im.tag_v2)
        self.check_values(doc, cm, self.zyx)
        self.assertEqual(mode, "P")
        for v in doc["class_map"]["values"]:
            self.assertEqual(palette[3 * v["value"]:3 * v["value"] + 3], v["rgb"], v["name"])
        self.assertIn("unit=micron", tags[270])
        self.assertIn("spacing=1.5", tags[270])
        self.assertAlmostEqual(float(tags[282]), 2.0, places=5)  # XResolution: pixels per unit kept

    def test_ome_zarr_class_map_sits_beside_the_input_labels(self):
        path = os.path.join(self.dir, "scene.ome.zarr")
        ome_zarr_writer.write_store(path, self.zyx, spacing_xyz=(0.5, 0.5, 1.5), unit="um", codec="zstd",
                                    chunks=(8, 16, 16))
        doc = predict(path, path)  # into the input store itself
        name = doc["class_map"]["name"]
        root = zarr.open(path, mode="r")
        self.assertEqual(root["labels"].attrs["labels"], ["cells", name])  # beside the input's label image
        attrs = dict(root["labels"][name].attrs)
        with open(SCHEMA) as f:
            jsonschema.validate(attrs, json.load(f))
        source = root["labels/cells"]
        self.assertEqual([a["name"] for a in attrs["multiscales"][0]["axes"]], ["z", "y", "x"])
        self.assertEqual({a["unit"] for a in attrs["multiscales"][0]["axes"]}, {"micrometer"})
        scale = attrs["multiscales"][0]["datasets"][0]["coordinateTransformations"][0]["scale"]
        np.testing.assert_allclose(scale, [1.5, 0.5, 0.5])  # the input's dataset scale times its multiscale scale
        array = root["labels"][name]["0"]
        self.assertEqual(array.chunks, source["0"].chunks)
        self.check_values(doc, np.asarray(array), np.asarray(source["0"]))
        # napari's colours and WISH's per-object properties: every object listed under its value, with its class.
        colours = {c["label-value"]: c["rgba"] for c in attrs["image-label"]["colors"]}
        for v in doc["class_map"]["values"]:
            self.assertEqual(colours[v["value"]], v["rgb"] + [255])
        listed = {o["label_id"]: (p["label-value"], o.get("class")) for p in attrs["image-label"]["properties"]
                  for o in p["objects"]}
        for r in doc["predictions"]:
            self.assertEqual(listed[r["label_id"]], (r["class_value"], r.get("label")))

    @unittest.skipIf(anndata is None, "needs python3-anndata")
    def test_the_table_is_one_row_per_object_in_csv_and_h5ad(self):
        path = os.path.join(self.dir, "table-scene.nii")
        labels = np.ascontiguousarray(self.zyx).tobytes()
        with open(path, "wb") as f:
            f.write(sv.nifti_bytes(labels))
        out = os.path.join(self.dir, "table-scene_classes.nii")
        doc = predict(path, out)
        base = os.path.join(self.dir, "table-scene_classes.objects")
        with open(base + ".csv") as f:
            rows = list(csv.DictReader(f))
        ad = anndata.read_h5ad(base + ".h5ad")
        self.assertEqual(ad.n_obs, len(rows))
        self.assertEqual(ad.n_obs, len(doc["predictions"]) + 1)  # every kept object and the speck
        self.assertEqual(list(ad.obs["label_id"]), [int(r["label_id"]) for r in rows])
        self.assertEqual(list(ad.obs["status"]), [r["status"] for r in rows])
        self.assertEqual(list(ad.obs["class_value"]), [int(r["class_value"]) for r in rows])
        speck = ad.obs[ad.obs["label_id"] == SPECK]
        self.assertEqual(list(speck["status"]), ["dropped"])
        self.assertTrue(speck["reason"].iloc[0].startswith("speck: 1 voxel"))
        by_id = {r["label_id"]: r for r in doc["predictions"]}
        lmax = 10
        self.assertEqual(list(ad.var_names[:lmax + 1]), ["xi_%d" % l for l in range(lmax + 1)])
        for i, label in enumerate(ad.obs["label_id"]):
            described = label in by_id and "error" not in by_id[label]
            self.assertEqual(bool(np.isfinite(ad.X[i, :lmax + 1]).all()), described, label)
            if described:
                self.assertEqual(ad.obs["class"].iloc[i], by_id[label]["label"])
                probs = {p["label"]: p["probability"] for p in by_id[label]["probabilities"]}
                for c, p in probs.items():
                    self.assertAlmostEqual(ad.obs["p_" + c].iloc[i], p, places=8)
        self.assertEqual(str(ad.obs["truncated"].dtype), "bool")

    def test_urocell_mask_gives_the_same_class_map_in_every_format(self):
        nii = os.path.join(SHARED, "urocell", "lyso", "binary", "fib1-3-3-0.nii.gz")
        if not os.path.exists(nii) or nibabel is None or Image is None:
            self.skipTest("needs ../shared/data/urocell, python3-nibabel and python3-pil")
        mask = np.asarray(nibabel.load(nii).dataobj).astype(np.uint8)  # x, y, z
        zyx = np.transpose(mask, (2, 1, 0))
        tif = os.path.join(self.dir, "lyso.tif")
        pages = [Image.fromarray(page) for page in zyx]
        pages[0].save(tif, save_all=True, append_images=pages[1:])
        store = os.path.join(self.dir, "lyso.ome.zarr")
        ome_zarr_writer.write_store(store, zyx, spacing_xyz=(16, 16, 15), unit="nm", codec="blosc", chunks=(64, 64, 64))
        common = ("--spacing", "16,16,15", "--unit", "nm")
        maps = {}
        docs = {}
        docs["nifti"] = predict(nii, os.path.join(self.dir, "lyso_classes.nii.gz"), *common)
        maps["nifti"] = np.transpose(np.asarray(nibabel.load(os.path.join(self.dir, "lyso_classes.nii.gz")).dataobj),
                                     (2, 1, 0))
        docs["tiff"] = predict(tif, os.path.join(self.dir, "lyso_classes.tif"), *common)
        with Image.open(os.path.join(self.dir, "lyso_classes.tif")) as im:
            maps["tiff"] = np.stack([np.array(f) for f in ImageSequence.Iterator(im)])
        docs["zarr"] = predict(store, store, *common)
        maps["zarr"] = np.asarray(zarr.open(store, mode="r")["labels"][docs["zarr"]["class_map"]["name"]]["0"])
        for fmt in ("tiff", "zarr"):
            self.assertEqual(class_values(docs[fmt]), class_values(docs["nifti"]), fmt)
            np.testing.assert_array_equal(maps[fmt], maps["nifti"], fmt)
        # The mask's objects are its 6-connected components (numpy's count); each carries its JSON value.
        from scipy import ndimage
        components, n = ndimage.label(zyx > 0)
        self.assertEqual(len(docs["nifti"]["predictions"]), n)
        for r in docs["nifti"]["predictions"]:
            centre = np.round(np.array(r["object"]["centroid"]) / np.array([16, 16, 15])).astype(int)
            component = components[tuple(centre[::-1])]
            if component:  # the centroid voxel may lie outside a curved object
                self.assertEqual(np.unique(maps["nifti"][components == component]).tolist(), [r["class_value"]])


if __name__ == "__main__":
    unittest.main()
