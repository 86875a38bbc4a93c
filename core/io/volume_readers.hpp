#pragma once
// Internal to core/io: the volume readers and what they share. read_volume (volume_reader.cpp) has checked the byte
// limit and chosen the format; each reader fills the image (dims, spacing, unit, labels), datatype and notes.

#include <cstdint>
#include <string>
#include <string_view>

#include "core/io/volume_io.hpp"

namespace wish::io_detail {

VolumeReadResult read_nifti(std::string_view bytes, const VolumeReadLimits& limits);
VolumeReadResult read_tiff(std::string_view bytes, const VolumeReadLimits& limits);
VolumeReadResult read_zarr_zip(std::string_view bytes, const VolumeReadOptions& options);  // zarr_reader.cpp
bool is_zarr_zip(std::string_view bytes);                                                  // zarr_store.cpp

enum class VoxelType { UInt8, Int8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };
const char* to_string(VoxelType type);
int byte_size(VoxelType type);

// Converts `count` voxels of `type` (byte-swapped when `swap`) into labels, throwing "invalid_label" with the voxel
// index (offset by `first_voxel`) for a negative, non-integer, non-finite or too large value.
void convert_labels(const unsigned char* data, std::int64_t count, VoxelType type, bool swap, std::uint32_t* out,
                    std::int64_t first_voxel, const char* format);

// Checks nx * ny * nz against the limit (without overflow) and throws LimitExceededError / parse_error.
std::int64_t checked_voxel_count(std::int64_t nx, std::int64_t ny, std::int64_t nz, const VolumeReadLimits& limits,
                                 const char* format);

}  // namespace wish::io_detail
