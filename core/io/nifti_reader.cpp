// NIfTI-1 single-file reader (.nii; .nii.gz through zlib). Header layout from the NIfTI-1 standard (nifti1.h):
// sizeof_hdr int32 @0 (= 348, which also tells the byte order), dim int16[8] @40, datatype int16 @70,
// bitpix int16 @72, pixdim float[8] @76, vox_offset float @108, scl_slope / scl_inter float @112 / @116,
// xyzt_units char @123, magic char[4] @344 ("n+1\0"). Voxel data x fastest, starting at vox_offset.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <zlib.h>

#include "core/common/errors.hpp"
#include "core/io/volume_readers.hpp"

namespace wish::io_detail {
namespace {

constexpr const char* kNiftiFormat = "nifti";

[[noreturn]] void fail(const std::string& message, const std::string& field) {
  throw InvalidInputError("parse_error", "NIfTI-1: " + message, {{"format", std::string(kNiftiFormat)}, {"field", field}});
}

// The first `want` bytes of the gzip stream (fewer when it ends first). Only what is asked for is allocated, so the
// header can be read, and the limits checked, before the voxel data is inflated.
std::string inflate_prefix(std::string_view gz, std::size_t want) {
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK) fail("zlib could not be initialised", "gzip");
  std::string out(want, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz.data()));
  std::size_t produced = 0;
  std::size_t consumed = 0;
  int rc = Z_OK;
  while (produced < want) {
    const std::size_t in_chunk = std::min<std::size_t>(gz.size() - consumed, 1u << 30);
    const std::size_t out_chunk = std::min<std::size_t>(want - produced, 1u << 30);
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz.data() + consumed));
    zs.avail_in = static_cast<uInt>(in_chunk);
    zs.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
    zs.avail_out = static_cast<uInt>(out_chunk);
    rc = inflate(&zs, Z_NO_FLUSH);
    consumed += in_chunk - zs.avail_in;
    produced += out_chunk - zs.avail_out;
    if (rc == Z_STREAM_END) break;
    if (rc != Z_OK) {
      const std::string why = zs.msg ? zs.msg : "error " + std::to_string(rc);
      inflateEnd(&zs);
      throw InvalidInputError("parse_error", "NIfTI-1: gzip data is corrupt after " + std::to_string(produced) +
                                                 " decompressed bytes (" + why + ")",
                              {{"format", std::string(kNiftiFormat)}, {"field", std::string("gzip")},
                               {"byte_offset", static_cast<std::int64_t>(produced)}});
    }
    if (zs.avail_in == 0 && consumed >= gz.size() && zs.avail_out != 0) break;  // input exhausted
  }
  inflateEnd(&zs);
  out.resize(produced);
  return out;
}

template <typename T>
T field(std::string_view h, std::size_t offset, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, h.data() + offset, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

bool voxel_type(int datatype, VoxelType& type) {
  switch (datatype) {
    case 2: type = VoxelType::UInt8; return true;
    case 4: type = VoxelType::Int16; return true;
    case 8: type = VoxelType::Int32; return true;
    case 16: type = VoxelType::Float32; return true;
    case 64: type = VoxelType::Float64; return true;
    case 256: type = VoxelType::Int8; return true;
    case 512: type = VoxelType::UInt16; return true;
    case 768: type = VoxelType::UInt32; return true;
    default: return false;
  }
}

}  // namespace

VolumeReadResult read_nifti(std::string_view bytes, const VolumeReadLimits& limits, bool probabilities) {
  const bool gz = bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f && static_cast<unsigned char>(bytes[1]) == 0x8b;
  std::string inflated;
  std::string_view h = bytes;
  if (gz) {
    inflated = inflate_prefix(bytes, 352);
    h = inflated;
  }
  if (h.size() < 348) fail("header is " + std::to_string(h.size()) + " bytes, needs 348", "sizeof_hdr");
  bool swap = false;
  if (field<std::int32_t>(h, 0, false) != 348) {
    if (field<std::int32_t>(h, 0, true) != 348)
      fail("sizeof_hdr is " + std::to_string(field<std::int32_t>(h, 0, false)) + ", expected 348", "sizeof_hdr");
    swap = true;
  }
  const std::string_view magic = h.substr(344, 4);
  if (magic == std::string_view("ni1\0", 4))
    fail("a header/image pair (.hdr + .img) cannot be read from one upload; save it as a single .nii", "magic");
  if (magic != std::string_view("n+1\0", 4)) fail("magic is not \"n+1\" (not a NIfTI-1 single file)", "magic");
  const int ndim = field<std::int16_t>(h, 40, swap);
  if (ndim < 1 || ndim > 7) fail("dim[0] is " + std::to_string(ndim) + ", must be 1 to 7", "dim");
  std::int64_t dim[8];
  for (int k = 1; k <= 7; ++k) dim[k] = k <= ndim ? field<std::int16_t>(h, 40 + 2 * k, swap) : 1;
  for (int k = 4; k <= ndim; ++k)
    if (dim[k] != 1)
      fail("dim[" + std::to_string(k) + "] is " + std::to_string(dim[k]) +
               ": only 3-D label images are read (one volume per file)", "dim");
  VoxelType type{};
  const int datatype = field<std::int16_t>(h, 70, swap);
  if (!voxel_type(datatype, type))
    throw InvalidInputError("unsupported_datatype", "NIfTI-1 datatype " + std::to_string(datatype) +
                                                        " is not a label type (uint8, int8, int16, uint16, int32, uint32, float32, float64)",
                            {{"format", std::string(kNiftiFormat)}, {"datatype", static_cast<std::int64_t>(datatype)}});
  const int bitpix = field<std::int16_t>(h, 72, swap);
  if (bitpix != 8 * byte_size(type))
    fail("bitpix is " + std::to_string(bitpix) + " but datatype " + to_string(type) + " has " +
             std::to_string(8 * byte_size(type)) + " bits", "bitpix");
  const float vox_offset = field<float>(h, 108, swap);
  if (!(std::isfinite(vox_offset) && vox_offset >= 348 && vox_offset == std::floor(vox_offset) && vox_offset < 1e9f))
    fail("vox_offset " + std::to_string(vox_offset) + " is not a whole byte offset >= 348", "vox_offset");
  const std::int64_t n = checked_voxel_count(dim[1], dim[2], dim[3], limits, kNiftiFormat);
  const std::uint64_t offset = static_cast<std::uint64_t>(vox_offset);
  const std::uint64_t need = offset + static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(byte_size(type));
  std::string_view data;
  std::string inflated_data;  // not `inflated`: the header view `h` still points into that string
  if (gz) {
    inflated_data = inflate_prefix(bytes, need);
    data = inflated_data;
  } else {
    data = bytes;
  }
  if (data.size() < need)
    throw InvalidInputError("parse_error", "NIfTI-1: truncated: " + std::to_string(n) + " voxels of " + to_string(type) +
                                               " at offset " + std::to_string(offset) + " need " + std::to_string(need) +
                                               " bytes, the data has " + std::to_string(data.size()),
                            {{"format", std::string(kNiftiFormat)}, {"field", std::string("data")},
                             {"byte_offset", static_cast<std::int64_t>(data.size())}});

  VolumeReadResult r;
  r.format = VolumeFormat::Nifti;
  r.datatype = to_string(type);
  r.image.dims = {dim[1], dim[2], dim[3]};
  r.image.labels.resize(static_cast<std::size_t>(n));
  if (probabilities) r.image.probability_scale = volume::LabelImage::kProbabilityScale;
  convert_labels(reinterpret_cast<const unsigned char*>(data.data() + offset), n, type, swap, r.image.labels.data(), 0,
                 kNiftiFormat, r.image.probability_scale);

  bool spacing_ok = true;
  for (int k = 0; k < 3; ++k) {
    const float p = field<float>(h, 80 + 4 * k, swap);  // pixdim[1..3]
    if (k < ndim && std::isfinite(p) && p > 0) r.image.spacing(k) = p;
    else if (k < ndim) spacing_ok = false;
  }
  r.spacing_from_file = spacing_ok;
  if (!spacing_ok) r.notes.push_back("pixdim is not positive: voxel size 1 assumed where missing");
  switch (static_cast<unsigned char>(h[123]) & 7) {
    case 1: r.image.unit = "m"; break;
    case 2: r.image.unit = "mm"; break;
    case 3: r.image.unit = "um"; break;
    default: r.image.unit = ""; break;
  }
  const float slope = field<float>(h, 112, swap), inter = field<float>(h, 116, swap);
  if ((slope != 0 && slope != 1) || inter != 0)
    r.notes.push_back("scl_slope/scl_inter (" + std::to_string(slope) + ", " + std::to_string(inter) +
                      ") ignored: labels are read as stored");
  NiftiGeometry g;
  for (int k = 0; k < 8; ++k) g.pixdim[static_cast<std::size_t>(k)] = field<float>(h, 76 + 4 * static_cast<std::size_t>(k), swap);
  g.xyzt_units = static_cast<std::uint8_t>(h[123]);
  g.qform_code = field<std::int16_t>(h, 252, swap);
  g.sform_code = field<std::int16_t>(h, 254, swap);
  for (std::size_t k = 0; k < 3; ++k) {
    g.quatern[k] = field<float>(h, 256 + 4 * k, swap);
    g.qoffset[k] = field<float>(h, 268 + 4 * k, swap);
  }
  for (std::size_t k = 0; k < 12; ++k) g.srow[k] = field<float>(h, 280 + 4 * k, swap);
  r.nifti = g;
  if (swap) r.notes.push_back("big-endian NIfTI-1");
  if (gz) r.notes.push_back("gzip-compressed");
  return r;
}

}  // namespace wish::io_detail
