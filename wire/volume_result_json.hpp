#pragma once
// The JSON of a label volume upload (VolumeResult in proto/openapi.json): what was read and how objects were found
// (VolumeSummary, with the `input` decision: kind of values, threshold, why, warnings), and one entry per kept object, in label-id order (VolumeObjectEntry): the object (voxel count,
// centroid in physical units, bounding box in voxel indices, truncated, genus, repairs, surface figures, timings)
// and either the object's DescribeResult or its error. Includes Eigen: never include from an http_*.cpp file.

#include <nlohmann/json.hpp>

#include "core/pipeline/volume_description.hpp"

namespace wish::wire {

nlohmann::json volume_summary_json(const VolumeSummary& summary);
// The "object" block of an object (core/pipeline/volume_description.hpp), the one encoder of it: the service's
// VolumeObjectEntry and the CLI's per-object rows (`wish describe|predict --json`) carry the same block. `unit` is
// the volume's, the unit of the centroid, area and volumes.
nlohmann::json volume_object_json(const VolumeObjectResult& object, const std::string& unit);
// The object's "topology" block: genus before, whether handles were removed, and how (method, voxels, volume change).
nlohmann::json topology_json(const SurfaceFigures& surface);

}  // namespace wish::wire
