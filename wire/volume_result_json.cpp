#include "wire/volume_result_json.hpp"

#include "wire/wire_json.hpp"

namespace wish::wire {

namespace {
nlohmann::json vec3(const Eigen::Vector3d& v) { return {json_number(v(0)), json_number(v(1)), json_number(v(2))}; }
}  // namespace

nlohmann::json volume_summary_json(const VolumeSummary& s) {
  return {{"format", to_string(s.format)},
          {"datatype", s.datatype},
          {"dims", {s.dims[0], s.dims[1], s.dims[2]}},
          {"spacing", vec3(s.spacing)},
          {"unit", s.unit},
          {"notes", s.notes},
          {"object_mode", volume::to_string(s.mode)},
          {"input", {{"kind", volume::to_string(s.input.kind)},
                     {"threshold", s.input.threshold ? nlohmann::json(*s.input.threshold) : nlohmann::json(nullptr)},
                     {"why", s.input.why},
                     {"warnings", s.input.warnings}}},
          {"objects_found", s.found},
          {"objects_kept", s.kept},
          {"dropped", {{"not_selected", s.dropped_not_selected}, {"small", s.dropped_small},
                       {"truncated", s.dropped_truncated}}},
          {"timings", {{"read", s.read_seconds}, {"objects", s.objects_seconds}}}};
}

nlohmann::json volume_object_json(const VolumeObjectResult& r, const std::string& unit) {
  const volume::VolumeObject& o = r.object;
  const SurfaceFigures& s = r.surface;
  return {{"voxel_count", o.voxel_count},
          {"centroid", vec3(o.centroid)},
          {"bbox_min", {o.bbox_min[0], o.bbox_min[1], o.bbox_min[2]}},
          {"bbox_max", {o.bbox_max[0], o.bbox_max[1], o.bbox_max[2]}},
          {"truncated", o.truncated},
          {"genus", s.genus},
          {"repairs", s.repairs},
          {"unit", unit},
          {"surface", {{"vertices", s.vertices},
                       {"faces", s.faces},
                       {"vertices_before_decimation", s.vertices_before_decimation},
                       {"area", json_number(s.area)},
                       {"volume", json_number(s.volume)},
                       {"voxel_volume", json_number(s.voxel_volume)}}},
          {"timings", {{"extraction", s.timings.extraction}, {"surface", s.timings.surface},
                       {"smoothing", s.timings.smoothing}, {"decimation", s.timings.decimation}}}};
}

}  // namespace wish::wire
