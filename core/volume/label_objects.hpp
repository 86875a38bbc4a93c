#pragma once
// The objects of a label image. In a label image (instances: Cellpose, PlantSeg, UroCell's mito/fv) every distinct
// non-zero value is one object; in a binary mask (every non-zero voxel has the same value: UroCell's lyso) every
// 6-connected component of foreground is one object. Auto mode chooses by that rule, and recognises masks with soft
// edges and probability maps, which it thresholds before taking components (input_kind.hpp; the decision is
// ObjectSet::input).
// An object is `truncated` when it touches the volume border (its true shape continues outside the image).
// Filters, applied in this order: label-id subset, minimum voxel count, border-touching objects.
// Limits: `max_objects` bounds the distinct objects found (checked while scanning, so a noise image cannot make the
// statistics tables grow without bound).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/volume/input_kind.hpp"
#include "core/volume/label_image.hpp"

namespace wish::volume {

enum class ObjectMode { Auto, Labels, Components };
const char* to_string(ObjectMode mode);

struct ObjectOptions {
  ObjectMode mode = ObjectMode::Auto;
  std::int64_t min_voxels = 0;          // objects with fewer voxels are dropped
  bool drop_truncated = false;          // drop objects touching the border (else kept, flagged truncated)
  std::vector<std::uint32_t> label_ids; // keep only these ids (label values, or component numbers); empty: all
  std::int64_t max_objects = 100'000;   // distinct objects found in one volume
  std::optional<double> threshold;      // foreground: value >= threshold (auto / components); absent: as decided
};

struct VolumeObject {
  std::uint32_t id = 0;                 // label value; for a mask, the component number (1-based, scan order z, y, x)
  std::int64_t voxel_count = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // physical units: mean voxel centre ⊙ spacing
  std::array<std::int64_t, 3> bbox_min{0, 0, 0};      // voxel indices, inclusive
  std::array<std::int64_t, 3> bbox_max{0, 0, 0};
  bool truncated = false;
};

struct ObjectSet {
  ObjectMode mode = ObjectMode::Labels;        // as resolved from Auto
  InputDecision input;                         // what the values are and why this mode (and threshold)
  std::vector<std::uint32_t> component_ids;    // Components mode: object id per voxel (0 background); else empty
  std::vector<VolumeObject> objects;           // kept objects, by id
  std::int64_t found = 0;                      // distinct objects before the filters
  std::int64_t dropped_not_selected = 0, dropped_small = 0, dropped_truncated = 0;

  // The object id of voxel i (the label itself, or its component number).
  std::uint32_t id_at(const LabelImage& image, std::size_t i) const {
    return mode == ObjectMode::Components ? component_ids[i] : image.labels[i];
  }
};

ObjectSet find_objects(const LabelImage& image, const ObjectOptions& options = {});

}  // namespace wish::volume
