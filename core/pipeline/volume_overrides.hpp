#pragma once
// The label-volume settings a front end may set, typed, with their one mapping onto the core's options: the
// service parses its volume parameters (?spacing=, ?objects=, ?min_voxels=, ...) into one
// (server/request_parsing.cpp), the CLI binds its flags (--spacing, --objects, --min-voxels, ...) to one
// (cli/volume_options.hpp), and both hand it to apply_overrides() over options that already hold their limits.
// Absent fields leave the core's defaults: the file's voxel size, auto object mode, the speck rule, fragments
// merged within kDefaultFragmentGap, handles repaired up to SurfaceOptions::kDefaultMaxRepairShare.
// Eigen-free (the service's request types are included beside httplib); the object modes' names are
// kObjectModeNames (core/volume/object_mode.hpp).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/volume/object_mode.hpp"

namespace wish {

struct VolumeOptions;

struct VolumeOverrides {
  std::optional<std::array<double, 3>> spacing;  // voxel size x, y, z: replaces the file's; each > 0
  std::optional<std::string> unit;               // "nm", "um", ...
  volume::ObjectMode objects = volume::ObjectMode::Auto;
  std::optional<double> threshold;               // foreground is value >= threshold (auto / components)
  std::optional<std::int64_t> min_voxels;        // a fixed bound instead of the speck rule (0: keep every object)
  std::optional<int> fragment_gap;               // mask fragments within this many voxels merge (< 0: never)
  bool drop_truncated = false;                   // drop objects touching the volume border
  std::vector<std::uint32_t> label_ids;          // only these label ids (empty: all)
  std::optional<double> max_repair_share;        // handle repair bound (0: never; infinity: always)
  std::optional<std::int64_t> target_vertices;   // decimation target per surface (0: keep all)
  std::optional<int> smoothing_iterations;       // Taubin iterations
  std::string label_image;                       // OME-Zarr: labels/<name> (empty: the first listed)
  int level = 0;                                 // OME-Zarr: multiscale level

  bool operator==(const VolumeOverrides&) const = default;
};

// The overrides over `options` (whose limits the caller has set). Throws InvalidInputError("invalid_parameter")
// for a voxel size that is not three finite positive numbers, a negative min_voxels or a negative repair bound.
void apply_overrides(const VolumeOverrides& overrides, VolumeOptions& options);

}  // namespace wish
