// NIfTI-1 single files in the browser (.nii, and .nii.gz through the browser's DecompressionStream): what the label
// volume view (volume_view.js) needs to show an uploaded label volume and its class map. Header fields as nifti1.h:
// sizeof_hdr int32 @0 (348 in the file's byte order), dim int16[8] @40, datatype int16 @70, pixdim float[8] @76,
// vox_offset float @108, magic @344 ("n+1"). Voxels x fastest.

const TYPES = {  // datatype -> [bytes, DataView getter]
  2: [1, 'getUint8'], 4: [2, 'getInt16'], 8: [4, 'getInt32'], 16: [4, 'getFloat32'], 64: [8, 'getFloat64'],
  256: [1, 'getInt8'], 512: [2, 'getUint16'], 768: [4, 'getUint32'],
};

async function gunzip(bytes) {
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('gzip'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

// {dims: [nx, ny, nz], spacing: [sx, sy, sz], values: Float64Array (x fastest)}; throws Error with the reason.
export async function readNifti(input) {
  let bytes = input instanceof Uint8Array ? input : new Uint8Array(input);
  if (bytes[0] === 0x1f && bytes[1] === 0x8b) bytes = await gunzip(bytes);
  if (bytes.length < 348) throw new Error('not a NIfTI-1 file (shorter than its header)');
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let little = true;
  if (view.getInt32(0, true) !== 348) {
    if (view.getInt32(0, false) !== 348) throw new Error('not a NIfTI-1 file (sizeof_hdr is not 348)');
    little = false;
  }
  const magic = String.fromCharCode(bytes[344], bytes[345], bytes[346]);
  if (magic !== 'n+1') throw new Error('not a NIfTI-1 single file (magic is not n+1)');
  const dims = [1, 2, 3].map((k) => view.getInt16(40 + 2 * k, little));
  const type = TYPES[view.getInt16(70, little)];
  if (!type) throw new Error(`NIfTI datatype ${view.getInt16(70, little)} is not a label type`);
  const spacing = [1, 2, 3].map((k) => view.getFloat32(76 + 4 * k, little) || 1);
  const offset = Math.round(view.getFloat32(108, little));
  const n = dims[0] * dims[1] * dims[2];
  const [size, getter] = type;
  if (offset + n * size > bytes.length) throw new Error('NIfTI-1 data is truncated');
  const values = new Float64Array(n);
  for (let i = 0; i < n; ++i) values[i] = size === 1 ? view[getter](offset + i) : view[getter](offset + i * size, little);
  return { dims, spacing, values };
}
