#pragma once
// Label volumes on `wish describe` and `wish predict`: one result row per kept object, keyed by label id. Each row
// starts {"file": volume, "label_id": id, "object": {voxel count, centroid, bounding box, truncated, genus, repairs,
// surface size and timings}, "input": {kind, threshold, why, warnings}}; the caller adds its result from the object's mesh, or the row gets "error" (a surface
// refused with its reason, or the describe/classify failure). A volume that cannot be read gives one row without a
// label id and its error. No object is dropped silently: objects removed by the filters are counted on the
// progress line (stderr), every kept one has a row.

#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/input_decision_text.hpp"
#include "core/common/errors.hpp"
#include "core/pipeline/volume_pipeline.hpp"

namespace wish::cli {

using VolumeObjectWork = std::function<void(nlohmann::json& row, Mesh mesh)>;
using VolumeRowFailure = std::function<void(nlohmann::json& row, const WishError& error)>;

inline nlohmann::json volume_object_json(const volume::VolumeObject& obj, const volume::ObjectSurface& s,
                                         const std::string& unit) {
  return {{"voxel_count", obj.voxel_count},
          {"centroid", {obj.centroid(0), obj.centroid(1), obj.centroid(2)}},
          {"bbox_min", obj.bbox_min},
          {"bbox_max", obj.bbox_max},
          {"truncated", obj.truncated},
          {"genus", s.genus},
          {"repairs", s.repairs},
          {"unit", unit},
          {"surface",
           {{"vertices", s.mesh.vertex_count()},
            {"faces", s.mesh.face_count()},
            {"area", s.area},
            {"volume", s.volume},
            {"voxel_volume", s.voxel_volume},
            {"timings",
             {{"extraction", s.timings.extraction},
              {"surface", s.timings.surface},
              {"smoothing", s.timings.smoothing},
              {"decimation", s.timings.decimation}}}}}};
}

// Appends one row per kept object of the volume in `bytes` to `rows` (or one error row for the volume).
inline void volume_rows(const std::string& file, const std::string& bytes, const VolumeOptions& options, bool progress,
                        const VolumeObjectWork& work, const VolumeRowFailure& fail, std::vector<nlohmann::json>& rows) {
  std::size_t total = 0, done = 0, failed = 0;
  std::string unit;
  nlohmann::json input;  // the object-finding decision, on every row of the volume
  try {
    for_each_object_surface(
        bytes, options,
        [&](std::size_t i, const volume::VolumeObject& obj, volume::ObjectSurface& s) {
          nlohmann::json row = {{"file", file}, {"label_id", obj.id}, {"object", volume_object_json(obj, s, unit)},
                                {"input", input}};
          try {
            if (!s.ok) throw WishError(ErrorCategory::Unmappable, s.refusal_code, s.refusal, {{"label_id", static_cast<std::int64_t>(obj.id)}});
            work(row, std::move(s.mesh));
            ++done;
          } catch (const WishError& e) {
            ++failed;
            fail(row, e);
          }
          rows.push_back(std::move(row));
          if (progress)
            std::cerr << "\r" << file << ": object " << (i + 1) << "/" << total << " (label " << obj.id << "), " << done
                      << " done, " << failed << " failed   " << std::flush;
        },
        [&](const VolumeSummary& summary) {
          total = static_cast<std::size_t>(summary.kept);
          unit = summary.unit;
          input = input_decision_json(summary.input);
          if (progress)
            std::cerr << file << ": " << summary.dims[0] << "x" << summary.dims[1] << "x" << summary.dims[2] << " "
                      << summary.datatype << ", " << volume::to_string(summary.mode) << ", " << summary.found
                      << " objects found, " << summary.kept << " kept (" << summary.dropped_small << " small, "
                      << summary.dropped_truncated << " truncated, " << summary.dropped_not_selected
                      << " not selected dropped)\n";
          print_input_decision(std::cerr, file, summary.input, !progress);
        });
    if (progress && total > 0) std::cerr << "\n";
  } catch (const WishError& e) {
    if (progress && done + failed > 0) std::cerr << "\n";
    nlohmann::json row = {{"file", file}};
    fail(row, e);
    rows.push_back(std::move(row));
  }
}

}  // namespace wish::cli
