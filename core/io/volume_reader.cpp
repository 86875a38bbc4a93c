#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "core/common/errors.hpp"
#include "core/io/volume_readers.hpp"

namespace wish {

const char* to_string(VolumeFormat format) {
  switch (format) {
    case VolumeFormat::Nifti: return "nifti";
    case VolumeFormat::Tiff: return "tiff";
    case VolumeFormat::OmeZarr: return "ome-zarr";
    default: return "unknown";
  }
}

namespace {

bool is_gzip(std::string_view b) { return b.size() >= 2 && static_cast<unsigned char>(b[0]) == 0x1f && static_cast<unsigned char>(b[1]) == 0x8b; }
bool is_tiff(std::string_view b) { return b.size() >= 4 && (b.substr(0, 4) == std::string_view("II*\0", 4) || b.substr(0, 4) == std::string_view("MM\0*", 4)); }
bool is_nifti(std::string_view b) {
  return b.size() >= 348 && (b.substr(344, 4) == std::string_view("n+1\0", 4) || b.substr(344, 4) == std::string_view("ni1\0", 4));
}

}  // namespace

VolumeFormat detect_volume_format(std::string_view bytes) {
  if (is_gzip(bytes)) return VolumeFormat::Nifti;  // the only gzip-wrapped volume we read; the reader checks the magic
  if (is_tiff(bytes)) return VolumeFormat::Tiff;
  if (is_nifti(bytes)) return VolumeFormat::Nifti;
  if (io_detail::is_zarr_zip(bytes)) return VolumeFormat::OmeZarr;
  return VolumeFormat::Unknown;
}

bool looks_like_volume(std::string_view bytes) { return detect_volume_format(bytes) != VolumeFormat::Unknown; }

bool is_volume_file_name(const std::filesystem::path& path) {
  std::string name = path.filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* ext : {".nii", ".nii.gz", ".tif", ".tiff", ".zarr.zip"})
    if (name.size() > std::strlen(ext) && name.ends_with(ext)) return true;
  return is_zarr_directory(path);
}

VolumeReadResult read_volume(std::string_view bytes, const VolumeReadOptions& options) {
  if (bytes.size() > options.limits.max_bytes)
    throw LimitExceededError("volume of " + std::to_string(bytes.size()) + " bytes exceeds the limit of " +
                                 std::to_string(options.limits.max_bytes) + " bytes",
                             {{"limit", std::string("max_bytes")}, {"value", static_cast<std::int64_t>(bytes.size())},
                              {"allowed", static_cast<std::int64_t>(options.limits.max_bytes)}});
  VolumeReadResult result;
  const VolumeFormat format = detect_volume_format(bytes);
  if (format == VolumeFormat::Unknown)
    throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_format",
                    "not a label volume: neither NIfTI-1 (.nii, .nii.gz), TIFF nor an OME-Zarr store's zip", {});
  auto read = [&](bool probabilities) {
    switch (format) {
      case VolumeFormat::Nifti: return io_detail::read_nifti(bytes, options.limits, probabilities);
      case VolumeFormat::Tiff: return io_detail::read_tiff(bytes, options.limits, probabilities);
      default: return io_detail::read_zarr_zip(bytes, options, probabilities);
    }
  };
  try {
    result = read(false);
  } catch (const io_detail::ProbabilityValuesFound&) {
    // A float that is not an integer: labels cannot hold it, a probability map can. Read again as one (rare, and
    // cheaper than holding every float volume twice).
    result = read(true);
    result.notes.push_back("floats that are not integers: read as a probability map (values in [0, 1])");
  }
  if (options.spacing_override) {
    const Eigen::Vector3d& s = *options.spacing_override;
    for (int k = 0; k < 3; ++k)
      if (!(std::isfinite(s(k)) && s(k) > 0))
        throw InvalidInputError("invalid_parameter", "voxel size must be three finite positive numbers (got " +
                                                         std::to_string(s(k)) + " along axis " + std::to_string(k) + ")",
                                {{"parameter", std::string("spacing")}, {"axis", static_cast<std::int64_t>(k)}});
    result.image.spacing = s;
    result.spacing_from_file = false;
    result.notes.push_back("voxel size set by the caller");
  }
  if (options.unit_override) result.image.unit = *options.unit_override;
  return result;
}

VolumeReadResult read_volume_file(const std::filesystem::path& path, const VolumeReadOptions& options) {
  if (is_zarr_directory(path)) return read_volume(read_zarr_directory(path, options), options);
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw IoError("file_not_found", "cannot read " + path.string() + ": " + ec.message(), {{"path", path.string()}});
  if (size > options.limits.max_bytes)
    throw LimitExceededError(path.string() + " has " + std::to_string(size) + " bytes, more than the limit of " +
                                 std::to_string(options.limits.max_bytes),
                             {{"limit", std::string("max_bytes")}, {"value", static_cast<std::int64_t>(size)},
                              {"allowed", static_cast<std::int64_t>(options.limits.max_bytes)}});
  std::ifstream in(path, std::ios::binary);
  std::string bytes(size, '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw IoError("file_not_found", "cannot read " + path.string(), {{"path", path.string()}});
  return read_volume(bytes, options);
}

namespace io_detail {

const char* to_string(VoxelType t) {
  switch (t) {
    case VoxelType::UInt8: return "uint8";
    case VoxelType::Int8: return "int8";
    case VoxelType::Int16: return "int16";
    case VoxelType::UInt16: return "uint16";
    case VoxelType::Int32: return "int32";
    case VoxelType::UInt32: return "uint32";
    case VoxelType::Int64: return "int64";
    case VoxelType::UInt64: return "uint64";
    case VoxelType::Float32: return "float32";
    case VoxelType::Float64: return "float64";
  }
  return "?";
}

int byte_size(VoxelType t) {
  switch (t) {
    case VoxelType::UInt8: case VoxelType::Int8: return 1;
    case VoxelType::Int16: case VoxelType::UInt16: return 2;
    case VoxelType::Int32: case VoxelType::UInt32: case VoxelType::Float32: return 4;
    case VoxelType::Int64: case VoxelType::UInt64: case VoxelType::Float64: return 8;
  }
  return 1;
}

namespace {

template <typename T>
T load(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

[[noreturn]] void bad_label(std::int64_t voxel, double value, const char* format, const char* why) {
  throw InvalidInputError("invalid_label", std::string(format) + " voxel " + std::to_string(voxel) + " holds " +
                                               std::to_string(value) + ", which is not a label (" + why + ")",
                          {{"voxel", voxel}, {"value", value}, {"format", std::string(format)}});
}

template <typename T>
void convert(const unsigned char* data, std::int64_t count, bool swap, std::uint32_t* out, std::int64_t first,
             const char* format, std::uint32_t probability_scale) {
  constexpr double kMax = static_cast<double>(std::numeric_limits<std::uint32_t>::max());
  for (std::int64_t i = 0; i < count; ++i) {
    const T v = load<T>(data + i * static_cast<std::int64_t>(sizeof(T)), swap);
    if constexpr (std::is_floating_point_v<T>) {
      const double d = static_cast<double>(v);
      if (!std::isfinite(d)) bad_label(first + i, d, format, "not finite");
      if (d < 0) bad_label(first + i, d, format, "negative");
      if (probability_scale > 0) {
        if (d > 1) bad_label(first + i, d, format, "above 1 in a probability map, whose values lie in [0, 1]");
        out[i] = static_cast<std::uint32_t>(std::lround(d * probability_scale));
        continue;
      }
      if (d != std::floor(d)) {
        if (d < 1)
          throw ProbabilityValuesFound("invalid_label", std::string(format) + " voxel " + std::to_string(first + i) +
                                                            " holds " + std::to_string(d) +
                                                            ": not a label; a probability map must hold values in [0, 1]",
                                       {{"voxel", first + i}, {"value", d}, {"format", std::string(format)}});
        bad_label(first + i, d, format, "not an integer, and above 1, so not a probability either");
      }
      if (d > kMax) bad_label(first + i, d, format, "above 2^32 - 1");
      out[i] = static_cast<std::uint32_t>(d);
    } else {
      if constexpr (std::is_signed_v<T>)
        if (v < 0) bad_label(first + i, static_cast<double>(v), format, "negative");
      if constexpr (sizeof(T) > 4)  // 64-bit labels (OME-Zarr's usual int64 / uint64) must fit in 32 bits
        if (static_cast<std::uint64_t>(v) > std::numeric_limits<std::uint32_t>::max())
          bad_label(first + i, static_cast<double>(v), format, "above 2^32 - 1");
      out[i] = static_cast<std::uint32_t>(v);
    }
  }
}

}  // namespace

void convert_labels(const unsigned char* data, std::int64_t count, VoxelType type, bool swap, std::uint32_t* out,
                    std::int64_t first_voxel, const char* format, std::uint32_t probability_scale) {
  switch (type) {
    case VoxelType::UInt8: convert<std::uint8_t>(data, count, false, out, first_voxel, format, 0); break;
    case VoxelType::Int8: convert<std::int8_t>(data, count, false, out, first_voxel, format, 0); break;
    case VoxelType::Int16: convert<std::int16_t>(data, count, swap, out, first_voxel, format, 0); break;
    case VoxelType::UInt16: convert<std::uint16_t>(data, count, swap, out, first_voxel, format, 0); break;
    case VoxelType::Int32: convert<std::int32_t>(data, count, swap, out, first_voxel, format, 0); break;
    case VoxelType::UInt32: convert<std::uint32_t>(data, count, swap, out, first_voxel, format, 0); break;
    case VoxelType::Int64: convert<std::int64_t>(data, count, swap, out, first_voxel, format, 0); break;
    case VoxelType::UInt64: convert<std::uint64_t>(data, count, swap, out, first_voxel, format, 0); break;
    case VoxelType::Float32: convert<float>(data, count, swap, out, first_voxel, format, probability_scale); break;
    case VoxelType::Float64: convert<double>(data, count, swap, out, first_voxel, format, probability_scale); break;
  }
}

std::int64_t checked_voxel_count(std::int64_t nx, std::int64_t ny, std::int64_t nz, const VolumeReadLimits& limits,
                                 const char* format) {
  for (std::int64_t n : {nx, ny, nz})
    if (n < 1)
      throw InvalidInputError("parse_error", std::string(format) + " volume has a dimension of " + std::to_string(n) +
                                                 " (each of nx, ny, nz must be at least 1)",
                              {{"format", std::string(format)}, {"field", std::string("dim")}, {"value", n}});
  const std::int64_t allowed = limits.max_voxels;
  auto over = [&](double value) {
    throw LimitExceededError(std::string(format) + " volume of " + std::to_string(nx) + " x " + std::to_string(ny) +
                                 " x " + std::to_string(nz) + " voxels exceeds the limit of " + std::to_string(allowed),
                             {{"limit", std::string("max_voxels")}, {"value", value}, {"allowed", allowed}});
  };
  if (nx > allowed || ny > allowed || nz > allowed || nx * ny > allowed || nx * ny * nz > allowed)
    over(static_cast<double>(nx) * static_cast<double>(ny) * static_cast<double>(nz));
  return nx * ny * nz;
}

}  // namespace io_detail
}  // namespace wish
