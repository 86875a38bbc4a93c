#pragma once
// Label volumes on `wish describe` and `wish predict`: one result row per kept object, keyed by label id. Each row
// starts {"file": volume, "label_id": id, "object": the object block of the service's VolumeObjectEntry (one
// encoder: wire/volume_result_json.hpp), "input": {kind, threshold, why, warnings} (how the volume's values were
// read)}; the caller renders the object's result into it, or the row gets "error"
// (core/pipeline/volume_description.hpp: a refused surface with its code's category — box_too_large is too_large,
// as the service's 413 — or the describe/classify failure). A volume that cannot be read gives one row without a
// label id and its error. No object is dropped silently: objects removed by the filters are counted on the
// progress line (stderr), every kept one has a row.

#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/input_decision_text.hpp"
#include "core/common/errors.hpp"
#include "core/pipeline/volume_description.hpp"
#include "wire/volume_result_json.hpp"

namespace wish::cli {

using VolumeObjectRender = std::function<void(nlohmann::json& row, const PipelineResult& result)>;
using VolumeRowFailure = std::function<void(nlohmann::json& row, const WishError& error)>;

// What else a command does with the volume as it goes (predict's class map and table): the summary once the objects
// are known, each object's result after its row is rendered (the row may be added to), and the read volume with
// its objects at the end.
struct VolumeRowHooks {
  std::function<void(const VolumeSummary&)> summary;
  std::function<void(const VolumeObjectResult&, nlohmann::json& row)> object;
  VolumeCompleteCallback complete;
};

// The stderr line of a volume's objects: found, kept, and each filter's drops.
inline void print_volume_counts(std::ostream& os, const std::string& file, const VolumeSummary& s) {
  os << file << ": " << s.dims[0] << "x" << s.dims[1] << "x" << s.dims[2] << " " << s.datatype << ", "
     << volume::to_string(s.mode) << ", " << s.found << " objects found, " << s.kept << " kept (dropped "
     << s.dropped_specks << " specks, " << s.dropped_small << " small, " << s.dropped_truncated << " truncated, "
     << s.dropped_not_selected << " not selected; " << s.fragments_merged << " fragments merged)\n";
}

// Appends one row per kept object of the volume in `bytes` to `rows` (or one error row for the volume).
inline void volume_rows(const std::string& file, const std::string& bytes, const VolumeOptions& options, bool progress,
                        const ObjectWork& work, const VolumeObjectRender& render, const VolumeRowFailure& fail,
                        std::vector<nlohmann::json>& rows, const VolumeRowHooks& hooks = {}) {
  std::size_t total = 0, done = 0, failed = 0;
  std::string unit;
  nlohmann::json input;  // the object-finding decision, on every row of the volume
  try {
    describe_volume(
        bytes, options, work,
        [&](std::size_t i, VolumeObjectResult& object) {
          nlohmann::json row = {{"file", file}, {"label_id", object.object.id},
                                {"object", wire::volume_object_json(object, unit)},
                                {"input", input}};
          if (object.ok()) {
            render(row, *object.result);
            ++done;
          } else {
            ++failed;
            fail(row, *object.error);
          }
          if (hooks.object) hooks.object(object, row);
          rows.push_back(std::move(row));
          if (progress)
            std::cerr << "\r" << file << ": object " << (i + 1) << "/" << total << " (label " << object.object.id
                      << "), " << done << " done, " << failed << " failed   " << std::flush;
        },
        Deadline{},
        [&](const VolumeSummary& summary) {
          total = static_cast<std::size_t>(summary.kept);
          unit = summary.unit;
          input = input_decision_json(summary.input);
          if (progress) print_volume_counts(std::cerr, file, summary);
          print_input_decision(std::cerr, file, summary.input, !progress);
          if (hooks.summary) hooks.summary(summary);
        },
        hooks.complete);
    if (progress && total > 0) std::cerr << "\n";
  } catch (const WishError& e) {
    if (progress && done + failed > 0) std::cerr << "\n";
    nlohmann::json row = {{"file", file}};
    fail(row, e);
    rows.push_back(std::move(row));
  }
}

}  // namespace wish::cli
