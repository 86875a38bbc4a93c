#pragma once
// The command-line options every subcommand that accepts label volumes shares (mesh-labels, describe, predict,
// train): voxel size and unit, object rule and filters, surface settings and limits.

#include <cmath>
#include <limits>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/common/errors.hpp"
#include "core/pipeline/volume_pipeline.hpp"

namespace wish::cli {

struct VolumeCliOptions {
  std::vector<double> spacing;   // x, y, z
  std::string unit;
  std::string objects = "auto";
  std::optional<std::int64_t> min_voxels;
  bool drop_truncated = false;
  std::vector<std::uint32_t> label_ids;
  std::int64_t target_vertices = 10'000;
  int smoothing_iterations = 10;
  bool close_handles = false;
  bool no_close_handles = false;
  std::int64_t max_voxels = 512ll * 512 * 512;
  std::int64_t max_objects = 100'000;
  std::int64_t max_object_box_voxels = volume::SurfaceOptions{}.max_box_voxels;
  std::optional<double> threshold;
  std::string zarr_labels;  // OME-Zarr: labels/<name> (empty: the first listed)
  int zarr_level = 0;       // OME-Zarr: multiscale level
};

inline void add_volume_options(CLI::App& sub, VolumeCliOptions& o) {
  sub.add_option("--spacing", o.spacing, "Voxel size x,y,z (overrides the file's)")->delimiter(',')->expected(3);
  sub.add_option("--unit", o.unit, "Unit of the voxel size (e.g. nm, um)");
  sub.add_option("--objects", o.objects, "Objects: labels (each value), components (6-connected parts of a mask), auto")
      ->check(CLI::IsMember({"auto", "labels", "components"}))->capture_default_str();
  sub.add_option("--threshold", o.threshold,
                 "Foreground is value >= T, then 6-connected components (default: half the maximum of a mask with "
                 "soft edges or a probability map, which auto recognises; a probability map's T is in [0, 1])");
  sub.add_option("--min-voxels", o.min_voxels,
                 "Drop objects with fewer voxels (default: drop specks, objects under 8 voxels or 0.5 % of the "
                 "volume's typical object; 0 keeps every object)");
  sub.add_flag("--drop-truncated", o.drop_truncated, "Drop objects touching the volume border (else flagged truncated)");
  sub.add_option("--label-ids", o.label_ids, "Only these label ids (comma-separated)")->delimiter(',');
  sub.add_option("--target-vertices", o.target_vertices, "Decimate each surface to about this many vertices (0: keep all)")
      ->capture_default_str();
  sub.add_option("--smoothing", o.smoothing_iterations, "Taubin smoothing iterations")->capture_default_str();
  sub.add_flag("--close-handles", o.close_handles,
               "Keep a morphological closing (radius up to 3) that makes a genus > 0 object genus 0, whatever volume it adds");
  sub.add_flag("--no-close-handles", o.no_close_handles,
               "Never close handles (by default a closing adding at most 1 % of an object's volume is kept, as a repair)")
      ->excludes("--close-handles");
  sub.add_option("--max-voxels", o.max_voxels, "Limit: voxels per volume")->capture_default_str();
  sub.add_option("--max-objects", o.max_objects, "Limit: objects per volume")->capture_default_str();
  sub.add_option("--max-object-box-voxels", o.max_object_box_voxels,
                 "Limit: padded bounding box of one object (past it: box_too_large, too_large as the service's 413)")
      ->capture_default_str();
  // Not --labels: `wish train --labels` names a manifest. As the HTTP API's ?label_image=.
  sub.add_option("--label-image", o.zarr_labels, "OME-Zarr: the label image labels/NAME to read (default: the first listed)");
  sub.add_option("--level", o.zarr_level, "OME-Zarr: multiscale level (0: full resolution)")->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

inline VolumeOptions to_volume_options(const VolumeCliOptions& o) {
  VolumeOptions v;
  if (!o.spacing.empty()) v.read.spacing_override = Eigen::Vector3d(o.spacing[0], o.spacing[1], o.spacing[2]);
  if (!o.unit.empty()) v.read.unit_override = o.unit;
  v.read.limits.max_voxels = o.max_voxels;
  v.read.zarr_labels = o.zarr_labels;
  v.read.zarr_level = o.zarr_level;
  v.objects.mode = o.objects == "labels" ? volume::ObjectMode::Labels
                   : o.objects == "components" ? volume::ObjectMode::Components : volume::ObjectMode::Auto;
  v.objects.min_voxels = o.min_voxels;
  v.objects.drop_truncated = o.drop_truncated;
  v.objects.label_ids = o.label_ids;
  v.objects.max_objects = o.max_objects;
  v.objects.threshold = o.threshold;
  v.surface.target_vertices = o.target_vertices;
  v.surface.smoothing_iterations = o.smoothing_iterations;
  v.surface.max_box_voxels = o.max_object_box_voxels;
  if (o.no_close_handles) v.surface.max_repair_share = 0;
  if (o.close_handles) v.surface.max_repair_share = std::numeric_limits<double>::infinity();
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
