#pragma once
// The command-line options every subcommand that accepts label volumes shares (mesh-labels, describe, predict,
// train): voxel size and unit, object rule and filters, surface settings (bound straight to the typed
// VolumeOverrides the service parses too, core/pipeline/volume_overrides.hpp) and the CLI's limits.

#include <cmath>
#include <limits>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/common/errors.hpp"
#include "cli/enum_option.hpp"
#include "core/pipeline/volume_overrides.hpp"
#include "core/pipeline/volume_pipeline.hpp"

namespace wish::cli {

struct VolumeCliOptions {
  VolumeOverrides overrides;  // the settings (core/pipeline/volume_overrides.hpp: one mapping, shared with the service)
  bool close_handles = false, no_close_handles = false;  // max_repair_share infinity / 0
  std::int64_t max_voxels = 512ll * 512 * 512;
  std::int64_t max_objects = 100'000;
  std::int64_t max_object_box_voxels = volume::SurfaceOptions{}.max_box_voxels;
};

inline void add_volume_options(CLI::App& sub, VolumeCliOptions& o) {
  VolumeOverrides& v = o.overrides;
  sub.add_option_function<std::vector<double>>(
         "--spacing", [&v](const std::vector<double>& s) { v.spacing = std::array<double, 3>{s[0], s[1], s[2]}; },
         "Voxel size x,y,z (overrides the file's)")
      ->delimiter(',')
      ->expected(3);
  sub.add_option_function<std::string>("--unit", [&v](const std::string& u) { v.unit = u; },
                                       "Unit of the voxel size (e.g. nm, um)");
  add_enum_option(sub, "--objects", v.objects, volume::kObjectModeNames,
                  "Objects: labels (each value), components (6-connected parts of a mask), auto (decided from the values)");
  sub.add_option("--threshold", v.threshold,
                 "Foreground is value >= T, then 6-connected components (default: half the maximum of a mask with "
                 "soft edges or a probability map, which auto recognises; a probability map's T is in [0, 1])");
  sub.add_option("--min-voxels", v.min_voxels,
                 "Drop objects with fewer voxels (default: drop specks, objects under 8 voxels or 0.5 % of the "
                 "volume's typical object; 0 keeps every object)");
  sub.add_option("--fragment-gap", v.fragment_gap,
                 "A mask component within this many background voxels of a dominant one (75 % of the foreground) is "
                 "its fragment, not an object (default 3; -1: never merge)");
  sub.add_flag("--drop-truncated", v.drop_truncated, "Drop objects touching the volume border (else flagged truncated)");
  sub.add_option("--label-ids", v.label_ids, "Only these label ids (comma-separated)")->delimiter(',');
  sub.add_option("--target-vertices", v.target_vertices, "Decimate each surface to about this many vertices (0: keep all)")
      ->default_str(std::to_string(volume::SurfaceOptions{}.target_vertices));
  sub.add_option("--smoothing", v.smoothing_iterations, "Taubin smoothing iterations")
      ->default_str(std::to_string(volume::SurfaceOptions{}.smoothing_iterations));
  auto* bound = sub.add_option("--max-repair-share", v.max_repair_share,
                               "Remove an object's handles (cut or fill, whichever changes less) when that changes at "
                               "most this share of its voxels")
                    ->default_str(std::to_string(volume::SurfaceOptions::kDefaultMaxRepairShare).substr(0, 4))
                    ->check(CLI::NonNegativeNumber);
  sub.add_flag("--close-handles", o.close_handles, "Remove handles whatever volume that changes")->excludes(bound);
  sub.add_flag("--no-close-handles", o.no_close_handles, "Never remove handles (a genus > 0 object is refused)")
      ->excludes("--close-handles")
      ->excludes(bound);
  sub.add_option("--max-voxels", o.max_voxels, "Limit: voxels per volume")->capture_default_str();
  sub.add_option("--max-objects", o.max_objects, "Limit: objects per volume")->capture_default_str();
  sub.add_option("--max-object-box-voxels", o.max_object_box_voxels,
                 "Limit: padded bounding box of one object (past it: box_too_large, too_large as the service's 413)")
      ->capture_default_str();
  // Not --labels: `wish train --labels` names a manifest. As the HTTP API's ?label_image=.
  sub.add_option("--label-image", v.label_image, "OME-Zarr: the label image labels/NAME to read (default: the first listed)");
  sub.add_option("--level", v.level, "OME-Zarr: multiscale level (0: full resolution)")->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

inline VolumeOptions to_volume_options(const VolumeCliOptions& o) {
  VolumeOptions v;
  v.read.limits.max_voxels = o.max_voxels;
  v.objects.max_objects = o.max_objects;
  v.surface.max_box_voxels = o.max_object_box_voxels;
  VolumeOverrides overrides = o.overrides;
  if (o.no_close_handles) overrides.max_repair_share = 0;
  if (o.close_handles) overrides.max_repair_share = std::numeric_limits<double>::infinity();
  apply_overrides(overrides, v);
  return v;
}

// "fib1-0-0-0.nii.gz" -> "fib1-0-0-0"; "cells.ome.zarr/" -> "cells".
inline std::string volume_stem(const std::string& path) {
  std::filesystem::path p(path);
  if (!p.has_filename()) p = p.parent_path();  // a store directory named with a trailing slash
  std::string name = p.filename().string();
  for (const char* ext : {".nii.gz", ".NII.GZ", ".nii", ".NII", ".tiff", ".TIFF", ".tif", ".TIF", ".ome.zarr.zip",
                          ".zarr.zip", ".ome.zarr", ".zarr", ".zip"}) {
    const std::string e = ext;
    if (name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0) return name.substr(0, name.size() - e.size());
  }
  return name;
}

}  // namespace wish::cli
