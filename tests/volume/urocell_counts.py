"""Independent count of UroCell's complete objects (numpy + gzip, no WISH code): objects of >= MIN voxels that do not
touch the volume border, per class. mito/instance and fv/instance: one object per label value; lyso/binary: one per
6-connected component (scipy.ndimage.label with its default cross structure = 6-connectivity).
Prints "class count" lines; used by tests/volume/urocell_test.cpp."""
import gzip
import os
import struct
import sys

import numpy as np
from scipy import ndimage


def read_nifti_gz(path):
    raw = gzip.open(path).read()
    dims = struct.unpack('<8h', raw[40:56])
    dtype = {2: np.uint8, 4: np.int16, 8: np.int32, 16: np.float32, 64: np.float64, 512: np.uint16, 768: np.uint32}[
        struct.unpack('<h', raw[70:72])[0]]
    offset = int(struct.unpack('<f', raw[108:112])[0])
    n = dims[1] * dims[2] * dims[3]
    data = np.frombuffer(raw, dtype=dtype, count=n, offset=offset)
    return data.reshape((dims[3], dims[2], dims[1])).astype(np.int64)  # z, y, x


def complete(labels, min_voxels):
    ids, counts = np.unique(labels[labels > 0], return_counts=True)
    border = set()
    for face in (labels[0], labels[-1], labels[:, 0], labels[:, -1], labels[:, :, 0], labels[:, :, -1]):
        border.update(np.unique(face[face > 0]).tolist())
    return sum(1 for i, c in zip(ids.tolist(), counts.tolist()) if c >= min_voxels and i not in border)


def main(root, min_voxels):
    for cls, sub, binary in (('mito', 'mito/instance', False), ('lyso', 'lyso/binary', True), ('fv', 'fv/instance', False)):
        total = 0
        for name in sorted(os.listdir(os.path.join(root, sub))):
            labels = read_nifti_gz(os.path.join(root, sub, name))
            if binary:
                labels, _ = ndimage.label(labels > 0)
            total += complete(labels, min_voxels)
        print(cls, total)


if __name__ == '__main__':
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 500)
