"""OME-Zarr label images written by Debian's python3-zarr (2.13, zarr v2), an independent writer for the reader's tests.

python3-zarr writes the arrays and chunks; the OME metadata (NGFF 0.4 .zattrs: multiscales with axes and scale
transformations, labels/ group, image-label) is written here, since ome-zarr-py is not packaged in Debian. Layout:
  <store>/.zattrs                 the image's multiscales (a placeholder intensity image, level 0 only)
  <store>/0                       the image array
  <store>/labels/.zattrs          {"labels": [names]}
  <store>/labels/<name>/.zattrs   multiscales (levels 0 and 1: 1 is every second voxel) + image-label
  <store>/labels/<name>/0, /1     the label arrays
Voxel size: dataset scale (spacing / 10) times a multiscale-wide scale of 10, so a reader must combine both.

Command line (used by tests/io/zarr_urocell_test.cpp): ome_zarr_writer.py IN.nii[.gz] OUT COMPRESSOR [zip]
writes the NIfTI volume (read with numpy, as tests/volume/urocell_counts.py does) as an OME-Zarr store directory, or as
a ZipStore zip when the fourth argument is "zip".
"""
import gzip
import struct
import sys

import numcodecs
import numpy as np
import zarr

UNITS = {"nm": "nanometer", "um": "micrometer", "mm": "millimeter", "m": "meter"}


def compressor(name):
    """zlib, gzip, zstd, blosc (lz4 + byte shuffle), blosc-zstd (zstd + bit shuffle), none."""
    return {
        "zlib": numcodecs.Zlib(level=3),
        "gzip": numcodecs.GZip(level=3),
        "zstd": numcodecs.Zstd(level=3),
        "blosc": numcodecs.Blosc(cname="lz4", clevel=5, shuffle=numcodecs.Blosc.SHUFFLE),
        "blosc-zstd": numcodecs.Blosc(cname="zstd", clevel=3, shuffle=numcodecs.Blosc.BITSHUFFLE),
        "none": None,
    }[name]


def write_ome_zarr(store, labels_zyx, spacing_xyz=(1.0, 1.0, 1.0), unit="um", codec="blosc", name="cells",
                   chunks=(16, 16, 16), order="C", dtype=None, extra_axes=(), other_labels=()):
    """Writes labels_zyx (numpy, z, y, x) as labels/<name> of an image. extra_axes: leading size-1 axes, e.g.
    (("t", "time"), ("c", "channel")). other_labels: names of further (empty) label images listed before <name>."""
    labels = np.asarray(labels_zyx)
    if dtype is not None:
        labels = labels.astype(dtype)
    lead = tuple(1 for _ in extra_axes)
    axes = [{"name": a, "type": t} for a, t in extra_axes] + [
        dict({"name": a, "type": "space"}, **({"unit": UNITS.get(unit, unit)} if unit else {}))
        for a in ("z", "y", "x")]
    sz, sy, sx = spacing_xyz[2], spacing_xyz[1], spacing_xyz[0]

    def multiscales(levels):
        return [{
            "version": "0.4",
            "name": name,
            "axes": axes,
            "datasets": [{"path": str(k), "coordinateTransformations": [
                {"type": "scale", "scale": list(lead) + [sz / 10 * 2 ** k, sy / 10 * 2 ** k, sx / 10 * 2 ** k]},
                {"type": "translation", "translation": list(lead) + [0.0, 0.0, 0.0]}]}
                for k in range(levels)],
            "coordinateTransformations": [{"type": "scale", "scale": [1.0] * len(lead) + [10.0, 10.0, 10.0]}],
        }]

    root = zarr.group(store=store, overwrite=True)
    root.create_dataset("0", data=np.zeros(lead + labels.shape, dtype="u1"), chunks=lead + tuple(chunks),
                        compressor=compressor("zlib"))
    root.attrs["multiscales"] = multiscales(1)
    group = root.create_group("labels")
    group.attrs["labels"] = list(other_labels) + [name]
    for other in other_labels:
        og = group.create_group(other)
        og.create_dataset("0", data=np.zeros(lead + (2, 2, 2), dtype="u1"), compressor=None)
        og.attrs.update({"multiscales": multiscales(1), "image-label": {"version": "0.4"}})
    lg = group.create_group(name)
    for k, level in enumerate((labels, labels[::2, ::2, ::2])):
        lg.create_dataset(str(k), data=level.reshape(lead + level.shape), chunks=lead + tuple(chunks),
                          compressor=compressor(codec), order=order, fill_value=0)
    # One write per .zattrs: a ZipStore appends every write as a new entry (zip names would repeat).
    lg.attrs.update({"multiscales": multiscales(2),
                     "image-label": {"version": "0.4", "colors": [], "source": {"image": "../../"}}})
    return root


def write_store(path, labels_zyx, zip_store=False, **kwargs):
    """A directory store at `path`, or a ZipStore zip (zarr's own zip layout) when zip_store."""
    if zip_store:
        store = zarr.ZipStore(path, mode="w")
        write_ome_zarr(store, labels_zyx, **kwargs)
        store.close()
    else:
        write_ome_zarr(zarr.DirectoryStore(path), labels_zyx, **kwargs)


def read_nifti(path):
    """(labels z, y, x as stored, spacing x, y, z, unit) of a NIfTI-1 single file, little endian, gzipped or not."""
    with open(path, "rb") as f:
        raw = f.read()
    if raw[:2] == b"\x1f\x8b":
        raw = gzip.decompress(raw)
    dims = struct.unpack("<8h", raw[40:56])
    dtype = {2: "<u1", 4: "<i2", 8: "<i4", 16: "<f4", 64: "<f8", 256: "<i1", 512: "<u2", 768: "<u4"}[
        struct.unpack("<h", raw[70:72])[0]]
    offset = int(struct.unpack("<f", raw[108:112])[0])
    pixdim = struct.unpack("<8f", raw[76:108])
    n = dims[1] * dims[2] * dims[3]
    data = np.frombuffer(raw, dtype=dtype, count=n, offset=offset).reshape((dims[3], dims[2], dims[1]))
    unit = {1: "m", 2: "mm", 3: "um"}.get(raw[123] & 7, "")
    return data, (pixdim[1], pixdim[2], pixdim[3]), unit


if __name__ == "__main__":
    src, out, codec = sys.argv[1], sys.argv[2], sys.argv[3]
    data, spacing, unit = read_nifti(src)
    # float64 label volumes (UroCell's fv) are stored as such: the reader must take float labels as the NIfTI one does.
    write_store(out, data, zip_store=len(sys.argv) > 4 and sys.argv[4] == "zip", spacing_xyz=spacing, unit=unit,
                codec=codec, chunks=(64, 64, 64))
