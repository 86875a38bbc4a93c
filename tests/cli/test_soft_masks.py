"""Soft-edged single-object masks as labs save them (issue 26 item 1), through the default path a user runs: no
--objects, no --threshold.

Each mask is one cell in a 32^3 8-bit volume stored as 0 and 255 with grey partial-volume levels along its boundary
(each boundary voxel's value is 255 x the share of 27 sub-voxel points inside the shape, as an area-averaging resize
leaves it), written here with struct as NIfTI-1 or as an uncompressed multi-page TIFF. Classes: spheres and
ellipsoids. `wish mesh-labels` must find one object (input soft_mask, threshold 127.5) where `--objects labels` finds
dozens of boundary slivers and warns; `wish train` on class folders of such masks must describe one sample per file.
Environment (set by ctest): WISH_BIN, the wish executable.
"""
import csv
import io
import json
import os
import shutil
import struct
import tempfile
import unittest

from wish_cli import WISH_BIN, read_text, run  # tests/testing

import synthetic_volume

N = 32


def soft_ellipsoid(centre, axes):
    """32^3 bytes: 255 inside, 0 outside, 255 x (inside share of 3^3 sub-points) on the boundary."""
    cx, cy, cz = centre
    a, b, c = axes
    margin = 1.0 / min(axes)  # a voxel's half-diagonal is under 0.87 voxel: beyond this band it is all in or out
    sub = (-1.0 / 3, 0.0, 1.0 / 3)
    data = bytearray(N * N * N)
    for z in range(N):
        for y in range(N):
            for x in range(N):
                q = (((x - cx) / a) ** 2 + ((y - cy) / b) ** 2 + ((z - cz) / c) ** 2) ** 0.5
                if q <= 1 - margin:
                    data[x + N * (y + N * z)] = 255
                elif q < 1 + margin:
                    inside = sum(1 for dz in sub for dy in sub for dx in sub
                                 if ((x + dx - cx) / a) ** 2 + ((y + dy - cy) / b) ** 2 + ((z + dz - cz) / c) ** 2 <= 1)
                    data[x + N * (y + N * z)] = round(255 * inside / 27)
    return bytes(data)


def tiff_bytes(data, dims=(N, N, N)):
    """Uncompressed little-endian multi-page TIFF, one 8-bit page per z slice."""
    nx, ny, nz = dims
    out = bytearray(b"II*\x00" + struct.pack("<I", 0))
    prev_next = 4  # where the previous "next IFD" offset is written
    for z in range(nz):
        strip = len(out)
        out += data[nx * ny * z:nx * ny * (z + 1)]
        if len(out) % 2:
            out += b"\x00"
        ifd = len(out)
        struct.pack_into("<I", out, prev_next, ifd)
        entries = [(256, 4, nx), (257, 4, ny), (258, 3, 8), (259, 3, 1), (262, 3, 1), (273, 4, strip),
                   (277, 3, 1), (278, 4, ny), (279, 4, nx * ny), (339, 3, 1)]
        out += struct.pack("<H", len(entries))
        for tag, typ, value in entries:
            out += struct.pack("<HHI", tag, typ, 1) + (struct.pack("<HH", value, 0) if typ == 3 else struct.pack("<I", value))
        prev_next = len(out)
        out += struct.pack("<I", 0)
    return bytes(out)


def write_mask(path, data):
    with open(path, "wb") as f:
        f.write(tiff_bytes(data) if path.endswith(".tif") else synthetic_volume.nifti_bytes(data, dims=(N, N, N)))


def sphere(k):
    return soft_ellipsoid((15.3 + 0.2 * k, 15.6, 15.1 + 0.1 * k), (9.0 + 0.3 * k,) * 3)


def ellipsoid(k):
    axes = [(12.0 + 0.3 * k), 6.5, 5.5 + 0.2 * k]
    axes = axes[k % 3:] + axes[:k % 3]  # the long axis along x, y or z
    return soft_ellipsoid((15.4, 15.2 + 0.2 * k, 15.7), tuple(axes))




class SoftMasks(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="wish_soft_masks_")
        cls.data = os.path.join(cls.dir, "classes")
        for cls_name, make in (("sphere", sphere), ("ellipsoid", ellipsoid)):
            os.makedirs(os.path.join(cls.data, cls_name))
            for k in range(6):
                write_mask(os.path.join(cls.data, cls_name, f"{cls_name}{k}.{'tif' if k % 2 else 'nii'}"), make(k))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_mask_has_many_grey_levels(self):
        grey = {v for v in sphere(0) if 0 < v < 255}
        self.assertGreater(len(grey), 15)  # what made the old auto rule find dozens of "labels"

    def test_mesh_labels_finds_one_object_by_default_and_says_why(self):
        for name in ("sphere0.nii", "sphere1.tif"):
            out = os.path.join(self.dir, "mesh-" + name)
            p = run("mesh-labels", os.path.join(self.data, "sphere", name), "--out", out)
            rows = list(csv.DictReader(io.StringIO(read_text(os.path.join(out, "objects.csv")))))
            self.assertEqual(len(rows), 1, p.stderr)
            self.assertEqual((rows[0]["input_kind"], rows[0]["threshold"], rows[0]["status"]), ("soft_mask", "127.5", "meshed"))
            self.assertIn("input soft_mask, threshold 127.5: 255 is the largest and most frequent", p.stderr)
            self.assertNotIn("warning", p.stderr)

    def test_read_as_labels_the_slivers_warn_with_the_option_that_helps(self):
        out = os.path.join(self.dir, "as-labels")
        p = run("mesh-labels", os.path.join(self.data, "sphere", "sphere0.nii"), "--out", out, "--objects", "labels",
                check=False)
        rows = list(csv.DictReader(io.StringIO(read_text(os.path.join(out, "objects.csv")))))
        self.assertGreater(len(rows), 15)
        self.assertIn("warning: the values look like a soft_mask", p.stderr)
        self.assertIn("components --threshold T", p.stderr)

    def test_describe_json_rows_carry_the_decision(self):
        p = run("describe", os.path.join(self.data, "ellipsoid", "ellipsoid1.tif"), "--json", "--lmax", "4", "--method", "cmcf",
                "--quiet")
        rows = json.loads(p.stdout)
        self.assertEqual(len(rows), 1)
        self.assertEqual(rows[0]["input"]["kind"], "soft_mask")
        self.assertEqual(rows[0]["input"]["threshold"], 127.5)
        self.assertIn("interpolated edges", rows[0]["input"]["why"])

    def test_train_on_class_folders_of_soft_masks_needs_no_extra_flags(self):
        model = os.path.join(self.dir, "model.json")
        report = os.path.join(self.dir, "report.json")
        desc = os.path.join(self.dir, "desc.csv")
        # No --objects, --threshold or --min-voxels; the other flags only make the grid search small.
        run("train", self.data, "--out", model, "--report", report, "--save-descriptors", desc, "--jobs", "1",
            "--nested-repeats", "0", "--grid-splits", "2", "--no-compare", "--quiet")
        rows = list(csv.DictReader(io.StringIO(read_text(desc))))
        self.assertEqual(len(rows), 12)  # one sample per mask, not one per grey level
        self.assertTrue(all(r["file"].endswith("#1") for r in rows), [r["file"] for r in rows])
        self.assertEqual(sorted({r["label"] for r in rows}), ["ellipsoid", "sphere"])
        rep = json.loads(read_text(report))
        self.assertEqual(rep["skipped"], [])
        # Predict on a fresh mask of each class.
        for cls_name, make in (("sphere", sphere), ("ellipsoid", ellipsoid)):
            path = os.path.join(self.dir, f"fresh-{cls_name}.nii")
            write_mask(path, make(7))
            preds = json.loads(run("predict", "--model", model, path, "--json", "--quiet").stdout)["predictions"]
            self.assertEqual([(r["label_id"], r["label"]) for r in preds], [(1, cls_name)])


if __name__ == "__main__":
    unittest.main()
