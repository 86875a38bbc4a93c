#pragma once
// What a label image holds, decided before its objects are found, and so how they are found. Labs save masks in
// more ways than "0 and one value": resampled masks keep grey levels along the boundary, probability maps keep a
// ramp from 0 to the maximum. Taken as labels, each grey level becomes an "object" (a sliver of the boundary).
// Kinds (figures in `why`):
//   labels          instances: each distinct non-zero value is one object
//   mask            one non-zero value: its 6-connected components are the objects
//   soft_mask       a mask with interpolated edges: the maximum value is the most frequent non-zero value, there
//                   are at least two other values, ≥ 90 % of their voxels lie within 2 voxels (26-neighbourhood
//                   steps) of a maximum-valued voxel (its boundary shell), and < 5 % of them lie inside a plateau of
//                   their own value (labels have inside voxels, boundary grey levels do not)
//   probability_map floats in [0, 1] (LabelImage::probability_scale), or 8/16-bit values whose maximum is the type's
//                   (255 / 65535), with 0 and the maximum on most voxels and at least two other values, in ramps
//                   (< 5 % of their voxels inside a plateau of their own value; a sigmoid's long tails make a low
//                   value, not the maximum, the most frequent non-zero one)
// A soft mask or probability map is thresholded at half its maximum (at or above: foreground) unless the caller
// sets the threshold, then its 6-connected components are the objects.
// A volume read as labels where most labels are boundary slivers (no voxel whose six neighbours share its label, and
// touching another label) gets a warning naming `--objects components --threshold`.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/volume/label_image.hpp"

namespace wish::volume {

enum class ObjectMode;  // Auto, Labels, Components: core/volume/object_mode.hpp

enum class InputKind { Labels, Mask, SoftMask, ProbabilityMap };
const char* to_string(InputKind kind);

struct InputDecision {
  InputKind kind = InputKind::Labels;      // what the values look like (whatever the mode)
  ObjectMode mode{};                       // how objects are found: Labels or Components once decided
  std::optional<double> threshold;         // Components: foreground is value >= threshold (in the file's values:
                                           // a probability for a float map); absent: every non-zero voxel
  std::string why;                         // one sentence with the figures the decision rests on
  std::vector<std::string> warnings;       // e.g. most labels are boundary slivers
};

// Decides kind, mode and threshold. `mode` Labels or Components are the caller's; a `threshold` given by the caller
// must be > 0 (and ≤ 1 for a float probability map) and cannot be combined with Labels mode ("invalid_parameter");
// a float probability map cannot be read as labels either.
InputDecision decide_input(const LabelImage& image, ObjectMode mode, std::optional<double> threshold);

// The smallest stored value that counts as foreground under the decision (1 when there is no threshold).
std::uint32_t foreground_floor(const LabelImage& image, const InputDecision& decision);

}  // namespace wish::volume
