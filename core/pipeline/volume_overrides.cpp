#include "core/pipeline/volume_overrides.hpp"

#include <cmath>

#include "core/common/errors.hpp"
#include "core/pipeline/volume_pipeline.hpp"

namespace wish {

void apply_overrides(const VolumeOverrides& o, VolumeOptions& v) {
  if (o.spacing) {
    for (int k = 0; k < 3; ++k)
      if (!(std::isfinite((*o.spacing)[k]) && (*o.spacing)[k] > 0))
        throw InvalidInputError("invalid_parameter", "voxel size must be three finite positive numbers",
                                {{"parameter", std::string("spacing")}, {"axis", std::int64_t{k}}});
    v.read.spacing_override = Eigen::Vector3d((*o.spacing)[0], (*o.spacing)[1], (*o.spacing)[2]);
  }
  if (o.unit) v.read.unit_override = *o.unit;
  v.read.zarr_labels = o.label_image;
  v.read.zarr_level = o.level;
  v.objects.mode = o.objects;
  v.objects.threshold = o.threshold;
  if (o.min_voxels && *o.min_voxels < 0)
    throw InvalidInputError("invalid_parameter", "min_voxels must be 0 or more", {{"parameter", std::string("min_voxels")}});
  v.objects.min_voxels = o.min_voxels;
  if (o.fragment_gap) v.objects.fragment_gap = *o.fragment_gap;
  v.objects.drop_truncated = o.drop_truncated;
  v.objects.label_ids = o.label_ids;
  if (o.max_repair_share) {
    if (!(*o.max_repair_share >= 0))
      throw InvalidInputError("invalid_parameter", "the handle repair bound must be 0 or more",
                              {{"parameter", std::string("max_repair_share")}});
    v.surface.max_repair_share = *o.max_repair_share;
  }
  if (o.target_vertices) v.surface.target_vertices = *o.target_vertices;
  if (o.smoothing_iterations) v.surface.smoothing_iterations = *o.smoothing_iterations;
}

}  // namespace wish
