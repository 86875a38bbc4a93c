"""Small synthetic label volumes for the service and client tests, written as NIfTI-1 by hand (stdlib only).

The default scene (ellipsoid_scene) in a 56 x 36 x 28 grid, x fastest:
  label 1: ellipsoid, centre (12, 14, 12), semi-axes (7, 5, 4) voxels
  label 2: ellipsoid, centre (30, 18, 14), semi-axes (8, 5, 5)
  label 3: a small ball of radius 1.5 (under 20 voxels: dropped by min_voxels=20)
  label 4: a 4 x 4 x 4 box in the corner at the origin (touches the border: truncated)
  label 5: a lattice of 2 x 2-voxel bars joining 4 x 4 x 4 nodes 4 voxels apart, x 40..53, y 11..24, z 7..20 (a
           sponge of genus 81: removing its handles would cut 81 bars, more than the default repair bound of 10 % of
           its voxels, so it is refused with genus_nonzero)
The torus the scene held before issue 39 is now repaired by default (its tube is cut): torus() below.
"""
import gzip
import struct

DIMS = (56, 36, 28)


def ellipsoid_scene(dims=DIMS):
    nx, ny, nz = dims
    labels = bytearray(nx * ny * nz)
    counts = {}

    def put(x, y, z, v):
        i = x + nx * (y + ny * z)
        if labels[i] == 0:
            labels[i] = v
            counts[v] = counts.get(v, 0) + 1

    for z in range(nz):
        for y in range(ny):
            for x in range(nx):
                if ((x - 12) / 7.0) ** 2 + ((y - 14) / 5.0) ** 2 + ((z - 12) / 4.0) ** 2 <= 1:
                    put(x, y, z, 1)
                elif ((x - 30) / 8.0) ** 2 + ((y - 18) / 5.0) ** 2 + ((z - 14) / 5.0) ** 2 <= 1:
                    put(x, y, z, 2)
                elif (x - 22) ** 2 + (y - 4) ** 2 + (z - 22) ** 2 <= 1.5 ** 2:
                    put(x, y, z, 3)
                elif x < 4 and y < 4 and z < 4:
                    put(x, y, z, 4)
                elif in_lattice(x, y, z):
                    put(x, y, z, 5)
    return bytes(labels), counts


def in_lattice(x, y, z, lo=(40, 11, 7), nodes=4, step=4, width=2):
    """Voxel on the bars of a cubic lattice: within its box and on at least two of the three node planes' bands."""
    on = 0
    for v, o in zip((x, y, z), lo):
        if not 0 <= v - o <= (nodes - 1) * step + width - 1:
            return False
        on += (v - o) % step < width
    return on >= 2


def torus(dims=DIMS, centre=(46, 18, 14), big=6.0, small=2.5, value=5):
    """A torus (genus 1; by default its handle is removed by cutting the tube, about 2.6 % of its voxels)."""
    nx, ny, nz = dims
    labels = bytearray(nx * ny * nz)
    for z in range(nz):
        for y in range(ny):
            for x in range(nx):
                rho = ((x - centre[0]) ** 2 + (y - centre[1]) ** 2) ** 0.5
                if (rho - big) ** 2 + (z - centre[2]) ** 2 <= small ** 2:
                    labels[x + nx * (y + ny * z)] = value
    return bytes(labels)


def nifti_bytes(labels, dims=DIMS, spacing=(1.0, 1.0, 1.0), units=2, gz=False):
    """NIfTI-1 single file, uint8 voxels (datatype 2), little endian; units: xyzt_units (2 mm, 3 um)."""
    nx, ny, nz = dims
    assert len(labels) == nx * ny * nz
    header = bytearray(348)
    struct.pack_into("<i", header, 0, 348)
    struct.pack_into("<8h", header, 40, 3, nx, ny, nz, 1, 1, 1, 1)
    struct.pack_into("<hh", header, 70, 2, 8)  # datatype uint8, bitpix 8
    struct.pack_into("<8f", header, 76, 1.0, spacing[0], spacing[1], spacing[2], 1.0, 1.0, 1.0, 1.0)
    struct.pack_into("<f", header, 108, 352.0)  # vox_offset
    struct.pack_into("<ff", header, 112, 1.0, 0.0)  # scl_slope, scl_inter
    header[123] = units
    header[344:348] = b"n+1\x00"
    data = bytes(header) + b"\x00\x00\x00\x00" + bytes(labels)
    return gzip.compress(data) if gz else data


def soft_ball(n=28, centre=(13.6, 13.3, 13.8), radius=8.3):
    """A mask with soft edges, as a resize leaves one: a ball stored as 0 and 255 with each boundary voxel at
    255 x the share of its 27 sub-voxel points inside (n^3 uint8 values, x fastest)."""
    cx, cy, cz = centre
    sub = (-1.0 / 3, 0.0, 1.0 / 3)
    data = bytearray(n * n * n)
    for z in range(n):
        for y in range(n):
            for x in range(n):
                d = ((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2) ** 0.5
                if d <= radius - 1:
                    data[x + n * (y + n * z)] = 255
                elif d < radius + 1:
                    inside = sum(1 for dz in sub for dy in sub for dx in sub
                                 if (x + dx - cx) ** 2 + (y + dy - cy) ** 2 + (z + dz - cz) ** 2 <= radius ** 2)
                    data[x + n * (y + n * z)] = round(255 * inside / 27)
    return bytes(data)
