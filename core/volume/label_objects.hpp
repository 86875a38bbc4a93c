#pragma once
// The objects of a label image. In a label image (instances: Cellpose, PlantSeg, UroCell's mito/fv) every distinct
// non-zero value is one object; in a binary mask (every non-zero voxel has the same value: UroCell's lyso) every
// 6-connected component of foreground is one object. Auto mode chooses by that rule, and recognises masks with soft
// edges and probability maps, which it thresholds before taking components (input_kind.hpp; the decision is
// ObjectSet::input).
// An object is `truncated` when it touches the volume border (its true shape continues outside the image).
// Specks and fragments (specks_and_fragments.hpp): in a mask, components near a dominant one are its fragments
// (merged into it, listed as its pieces); objects too small to be one are specks.
// Filters, applied in this order: label-id subset, specks (or a fixed minimum voxel count), border-touching objects.
// Every object a filter drops is listed in ObjectSet::dropped with its reason, never dropped silently.
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
#include "core/volume/object_mode.hpp"
#include "core/volume/specks_and_fragments.hpp"

namespace wish::volume {


struct ObjectOptions {
  ObjectMode mode = ObjectMode::Auto;
  std::optional<std::int64_t> min_voxels;  // objects with fewer voxels are dropped ("small"); absent: the speck rule
  int fragment_gap = kDefaultFragmentGap;  // mask fragments within this many background voxels merge (< 0: never)
  bool drop_truncated = false;          // drop objects touching the border (else kept, flagged truncated)
  std::vector<std::uint32_t> label_ids; // keep only these ids (label values, or component numbers); empty: all
  std::int64_t max_objects = 100'000;   // distinct objects found in one volume
  std::optional<double> threshold;      // foreground: value >= threshold (auto / components); absent: as decided
};

// A fragment merged into an object: a component of a mask near the object's main piece.
struct ObjectPiece {
  std::uint32_t component = 0;   // its component number (scan order, as object ids in components mode)
  std::int64_t voxel_count = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // physical units
  int gap = 0;                   // background voxels between it and the main piece (0: touching diagonally)
};

struct VolumeObject {
  std::uint32_t id = 0;                 // label value; for a mask, the component number (1-based, scan order z, y, x)
  std::int64_t voxel_count = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // physical units: mean voxel centre ⊙ spacing
  std::array<std::int64_t, 3> bbox_min{0, 0, 0};      // voxel indices, inclusive
  std::array<std::int64_t, 3> bbox_max{0, 0, 0};
  bool truncated = false;
  std::vector<ObjectPiece> fragments;  // merged pieces (counted in voxel_count, centroid and box); empty for labels
};

enum class DropReason { NotSelected, Speck, Small, Truncated };
const char* to_string(DropReason reason);  // "not_selected", "speck", "small", "truncated"

struct DroppedObject {
  VolumeObject object;
  DropReason reason = DropReason::Speck;
  std::string why;  // "3 voxels, under 8 (the volume's typical object has 12000 voxels; ...)"
};

struct ObjectSet {
  ObjectMode mode = ObjectMode::Labels;        // as resolved from Auto
  InputDecision input;                         // what the values are and why this mode (and threshold)
  std::vector<std::uint32_t> component_ids;    // Components mode: object id per voxel (0 background); else empty
  std::vector<VolumeObject> objects;           // kept objects, by id
  std::vector<DroppedObject> dropped;          // objects the filters dropped, by id
  std::int64_t found = 0;                      // distinct objects before the filters (fragments merged)
  std::int64_t fragments_merged = 0;           // mask components merged into another as fragments
  SpeckRule specks;                            // the rule as applied (below = 0 when min_voxels was given)
  std::int64_t dropped_not_selected = 0, dropped_specks = 0, dropped_small = 0, dropped_truncated = 0;

  // The object id of voxel i (the label itself, or its component number).
  std::uint32_t id_at(const LabelImage& image, std::size_t i) const {
    return mode == ObjectMode::Components ? component_ids[i] : image.labels[i];
  }
};

ObjectSet find_objects(const LabelImage& image, const ObjectOptions& options = {});

}  // namespace wish::volume
