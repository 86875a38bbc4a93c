#pragma once
// Internal to core/io: the volume readers and what they share. read_volume (volume_reader.cpp) has checked the byte
// limit and chosen the format; each reader fills the image (dims, spacing, unit, labels), datatype and notes.

#include <cstdint>
#include <string>
#include <string_view>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"

namespace wish::io_detail {

// `probabilities`: float voxels are probabilities in [0, 1] (stored as fixed point, LabelImage::probability_scale),
// set by read_volume when the first reading found a non-integer float (ProbabilityValuesFound).
VolumeReadResult read_nifti(std::string_view bytes, const VolumeReadLimits& limits, bool probabilities = false);
VolumeReadResult read_tiff(std::string_view bytes, const VolumeReadLimits& limits, bool probabilities = false);
// `probabilities` as above (a float zarr array of values in [0, 1]).
VolumeReadResult read_zarr_zip(std::string_view bytes, const VolumeReadOptions& options,
                               bool probabilities = false);  // zarr_reader.cpp
bool is_zarr_zip(std::string_view bytes);                    // zarr_store.cpp

enum class VoxelType { UInt8, Int8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };
const char* to_string(VoxelType type);
int byte_size(VoxelType type);

// Converts `count` voxels of `type` (byte-swapped when `swap`) into labels, throwing "invalid_label" with the voxel
// index (offset by `first_voxel`) for a negative, non-integer, non-finite or too large value. A float that is not an
// integer but lies in [0, 1] throws ProbabilityValuesFound (an "invalid_label" too, so a reader that does not retry
// still answers a clear error): the volume may be a probability map, which read_volume reads again with
// `probability_scale` > 0 (floats must then lie in [0, 1] and are stored as round(p × probability_scale)).
struct ProbabilityValuesFound : InvalidInputError {
  using InvalidInputError::InvalidInputError;
};
void convert_labels(const unsigned char* data, std::int64_t count, VoxelType type, bool swap, std::uint32_t* out,
                    std::int64_t first_voxel, const char* format, std::uint32_t probability_scale = 0);

// Checks nx * ny * nz against the limit (without overflow) and throws LimitExceededError / parse_error.
std::int64_t checked_voxel_count(std::int64_t nx, std::int64_t ny, std::int64_t nz, const VolumeReadLimits& limits,
                                 const char* format);

}  // namespace wish::io_detail
