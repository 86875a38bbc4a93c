#pragma once
// Label volume -> one surface per object: read (core/io/volume_io.hpp) -> objects (core/volume/label_objects.hpp)
// -> surface per object (core/volume/object_surface.hpp). Objects are handed to a callback one at a time, so a
// volume with thousands of objects never holds all their meshes at once. Used by `wish mesh-labels`,
// `wish describe/predict/train` on volumes and the service's volume uploads.

#include <functional>
#include <string_view>

#include "core/io/volume_io.hpp"
#include "core/volume/label_objects.hpp"
#include "core/volume/object_surface.hpp"

namespace wish {

struct VolumeOptions {
  VolumeReadOptions read;
  volume::ObjectOptions objects;
  volume::SurfaceOptions surface;
};

struct VolumeSummary {
  VolumeFormat format = VolumeFormat::Unknown;
  std::string datatype;
  std::array<std::int64_t, 3> dims{0, 0, 0};
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();
  std::string unit;
  std::vector<std::string> notes;
  volume::ObjectMode mode = volume::ObjectMode::Labels;
  volume::InputDecision input;  // kind of values, threshold and why (core/volume/input_kind.hpp)
  std::int64_t found = 0, kept = 0, dropped_not_selected = 0, dropped_specks = 0, dropped_small = 0, dropped_truncated = 0;
  std::int64_t fragments_merged = 0;                // mask components merged into an object as its fragments
  volume::SpeckRule specks;                         // as applied (below 0: min_voxels was given)
  std::vector<volume::DroppedObject> dropped;       // every object a filter dropped, with its reason, by id
  double read_seconds = 0, objects_seconds = 0;
};

// Called once per kept object, in id order, with its index among the kept ones. The surface may be moved from.
using ObjectCallback = std::function<void(std::size_t index, const volume::VolumeObject& object, volume::ObjectSurface& surface)>;
// Called with the summary once the objects are known, before the first object callback.
using SummaryCallback = std::function<void(const VolumeSummary& summary)>;

// Called once after the last object with what was read and the objects found, before they are freed: lets a caller
// write an image of the objects (the class map, class_map.hpp) without reading the volume again.
using VolumeCompleteCallback = std::function<void(const VolumeReadResult& read, const volume::ObjectSet& objects)>;

VolumeSummary for_each_object_surface(std::string_view bytes, const VolumeOptions& options,
                                      const ObjectCallback& on_object, const SummaryCallback& on_summary = {},
                                      const VolumeCompleteCallback& on_complete = {});

}  // namespace wish
