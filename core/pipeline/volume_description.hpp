#pragma once
// The one owner of a label-volume object. describe_volume() takes every kept object of a label volume through its
// surface (volume_pipeline.hpp) and the caller's work on that surface (describe, classify, or write it), and hands
// each object on as one VolumeObjectResult: the voxel object, its surface's figures, and the work's result or the
// object's error. A refused surface becomes an error with the category the code table gives its code
// (core/common/error_codes.hpp: box_too_large is TooLarge, 413; genus_nonzero Unmappable, 422), the same in every
// front end. The service (server/compute_service.cpp), the CLI (describe and predict through cli/volume_rows.hpp,
// mesh-labels) and training (core/training/training_set.cpp) render it; wire/volume_result_json.hpp is its one
// JSON encoder.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/common/deadline.hpp"
#include "core/common/errors.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/pipeline/volume_pipeline.hpp"

namespace wish {

// What an object's surface was, kept when its mesh moves on to the work.
struct SurfaceFigures {
  int genus = -1;  // of the voxel object's surface before any repair (-1: not a closed surface)
  volume::TopologyRepairFigures repair;  // genus > 0: what removing the handles changes
  bool repaired = false;                 // and whether that repair was kept
  std::vector<std::string> repairs;
  std::int64_t vertices = 0, faces = 0, vertices_before_decimation = 0;
  double area = 0, volume = 0, voxel_volume = 0, raw_area = 0;  // in the volume's unit (squared, cubed)
  volume::SurfaceTimings timings;
};

struct VolumeObjectResult {
  volume::VolumeObject object;
  SurfaceFigures surface;
  std::optional<PipelineResult> result;  // what the work returned (none for a work that only writes the mesh)
  std::optional<WishError> error;        // the surface's refusal or the work's failure
  bool ok() const { return !error.has_value(); }
};

// The work on one accepted surface: describe or classify it (a result), or write it (no result). A WishError it
// throws is the object's error, except a timeout or a cancellation, which ends the whole volume.
using ObjectWork = std::function<std::optional<PipelineResult>(const volume::VolumeObject& object, Mesh mesh)>;
// Called once per kept object, in label-id order, with its index among the kept ones; the result may be moved from.
using ObjectResultCallback = std::function<void(std::size_t index, VolumeObjectResult& object)>;

// Throws what reading and finding objects throw (InvalidInput, UnsupportedFormat, TooLarge: volume_pipeline.hpp).
// The deadline is checked once, before each object's work: past it the volume fails with TimeoutError "time limit
// exceeded after i of n objects" (details stage, objects_done, objects), cancelled with the deadline's error.
VolumeSummary describe_volume(std::string_view bytes, const VolumeOptions& options, const ObjectWork& work,
                              const ObjectResultCallback& on_object, const Deadline& deadline = {},
                              const SummaryCallback& on_summary = {}, const VolumeCompleteCallback& on_complete = {});

// The refusal of a surface as an error: its code's category from the code table (Unmappable for a code it does
// not list), details label_id and genus.
WishError surface_refusal_error(const volume::VolumeObject& object, const volume::ObjectSurface& surface);

// The refusal of a volume with no object to describe (every voxel background, or every object filtered out): an
// Unmappable "no_objects" that says which filter took them, so that a batch script does not read an empty list as
// success. Details objects_found, not_selected, small, truncated.
WishError no_objects_error(const VolumeSummary& summary);

}  // namespace wish
