#include "wire/volume_result_json.hpp"

#include "wire/wire_json.hpp"

namespace wish::wire {

namespace {
nlohmann::json vec3(const Eigen::Vector3d& v) { return {json_number(v(0)), json_number(v(1)), json_number(v(2))}; }

nlohmann::json dropped_json(const volume::DroppedObject& d) {
  const volume::VolumeObject& o = d.object;
  return {{"label_id", o.id},
          {"reason", volume::to_string(d.reason)},
          {"why", d.why},
          {"voxel_count", o.voxel_count},
          {"centroid", vec3(o.centroid)},
          {"bbox_min", {o.bbox_min[0], o.bbox_min[1], o.bbox_min[2]}},
          {"bbox_max", {o.bbox_max[0], o.bbox_max[1], o.bbox_max[2]}},
          {"truncated", o.truncated}};
}
}  // namespace

nlohmann::json topology_json(const SurfaceFigures& s) {
  const volume::TopologyRepairFigures& r = s.repair;
  nlohmann::json out = {{"genus_before", s.genus}, {"repaired", s.repaired}};
  if (s.genus > 0)
    out["repair"] = {{"method", r.method()},       {"handles_cut", r.cuts},
                     {"tunnels_filled", r.fills},   {"voxels_removed", r.removed},
                     {"voxels_added", r.added},     {"volume_change", json_number(r.volume_change())},
                     {"cut_every_handle", r.cut_every_handle}, {"fill_every_tunnel", r.fill_every_tunnel},
                     {"text", r.describe()}};
  return out;
}

nlohmann::json volume_summary_json(const VolumeSummary& s) {
  nlohmann::json dropped = nlohmann::json::array();
  for (const volume::DroppedObject& d : s.dropped) dropped.push_back(dropped_json(d));
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
          {"dropped", {{"not_selected", s.dropped_not_selected}, {"speck", s.dropped_specks}, {"small", s.dropped_small},
                       {"truncated", s.dropped_truncated}}},
          {"speck_rule", s.specks.below > 0 ? nlohmann::json{{"typical_voxels", s.specks.typical_voxels},
                                                             {"below", s.specks.below}}
                                            : nlohmann::json(nullptr)},
          {"fragments_merged", s.fragments_merged},
          {"dropped_objects", dropped},
          {"timings", {{"read", s.read_seconds}, {"objects", s.objects_seconds}}}};
}

nlohmann::json volume_object_json(const VolumeObjectResult& r, const std::string& unit) {
  const volume::VolumeObject& o = r.object;
  const SurfaceFigures& s = r.surface;
  nlohmann::json fragments = nlohmann::json::array();
  for (const volume::ObjectPiece& p : o.fragments)
    fragments.push_back({{"component", p.component}, {"voxel_count", p.voxel_count}, {"centroid", vec3(p.centroid)},
                         {"gap", p.gap}});
  return {{"voxel_count", o.voxel_count},
          {"centroid", vec3(o.centroid)},
          {"bbox_min", {o.bbox_min[0], o.bbox_min[1], o.bbox_min[2]}},
          {"bbox_max", {o.bbox_max[0], o.bbox_max[1], o.bbox_max[2]}},
          {"truncated", o.truncated},
          {"genus", s.genus},
          {"topology", topology_json(s)},
          {"fragments", fragments},
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
