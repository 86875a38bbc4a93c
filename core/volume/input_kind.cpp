#include "core/volume/input_kind.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>

#include "core/common/errors.hpp"
#include "core/volume/label_objects.hpp"

namespace wish::volume {

const char* to_string(InputKind kind) {
  switch (kind) {
    case InputKind::Labels: return "labels";
    case InputKind::Mask: return "mask";
    case InputKind::SoftMask: return "soft_mask";
    case InputKind::ProbabilityMap: return "probability_map";
  }
  return "?";
}

namespace {

// The rule's figures (input_kind.hpp) and why: a resampled mask's grey levels sit within one or two voxels of the
// full value (one voxel for a downsampling, two for an upsampling by up to 2); a label image's labels have inside
// voxels unless they are a few voxels thin; a few percent of exceptions absorb noise and thin parts.
constexpr double kShellShare = 0.90;
constexpr int kShellRadius = 2;
constexpr double kPlateauShare = 0.05;
constexpr double kZeroAndMaxShare = 0.5;
constexpr std::size_t kMaxDistinctTracked = 1u << 20;  // beyond: not a mask of any kind; labels (and their limit)

std::string fmt(const char* format, double a = 0, double b = 0, double c = 0, double d = 0) {
  char buf[320];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

std::string value_text(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

struct ValueStats {
  std::int64_t voxels = 0, zeros = 0;
  std::uint32_t max_value = 0, top_value = 0;
  std::int64_t at_max = 0, top_count = 0;
  std::unordered_map<std::uint32_t, std::int64_t> counts;  // non-zero values
  bool capped = false;                                    // more distinct values than tracked
};

ValueStats value_stats(const LabelImage& image) {
  ValueStats s;
  s.voxels = static_cast<std::int64_t>(image.labels.size());
  std::uint32_t last = 0;
  std::int64_t* last_count = nullptr;
  for (std::uint32_t v : image.labels) {
    if (v == 0) {
      ++s.zeros;
      continue;
    }
    s.max_value = std::max(s.max_value, v);
    if (s.capped) continue;
    if (v != last || last_count == nullptr) {
      if (s.counts.size() >= kMaxDistinctTracked && s.counts.find(v) == s.counts.end()) {
        s.capped = true;
        continue;
      }
      last = v;
      last_count = &s.counts[v];
    }
    ++*last_count;
  }
  for (const auto& [v, n] : s.counts)
    if (n > s.top_count || (n == s.top_count && v > s.top_value)) s.top_value = v, s.top_count = n;
  const auto it = s.counts.find(s.max_value);
  s.at_max = it == s.counts.end() ? 0 : it->second;
  return s;
}

// Voxels within Chebyshev distance `r` of a voxel holding `value` (a box dilation, one axis at a time).
std::vector<std::uint8_t> near_value(const LabelImage& image, std::uint32_t value, int r) {
  std::vector<std::uint8_t> near(image.labels.size());
  for (std::size_t i = 0; i < near.size(); ++i) near[i] = image.labels[i] == value;
  const std::int64_t n[3] = {image.dims[0], image.dims[1], image.dims[2]};
  const std::int64_t stride[3] = {1, n[0], n[0] * n[1]};
  std::vector<std::uint8_t> line;
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // the other two axes enumerate the lines
    const std::int64_t len = n[axis], st = stride[axis];
    line.resize(static_cast<std::size_t>(len));
    for (std::int64_t ib = 0; ib < n[b]; ++ib)
      for (std::int64_t ia = 0; ia < n[a]; ++ia) {
        const std::int64_t start = ia * stride[a] + ib * stride[b];
        std::int64_t last_one = -1'000'000;
        for (std::int64_t k = 0; k < len; ++k) {  // forward: a set voxel at most r behind
          if (near[static_cast<std::size_t>(start + k * st)]) last_one = k;
          line[static_cast<std::size_t>(k)] = k - last_one <= r;
        }
        std::int64_t next_one = 1'000'000'000;
        for (std::int64_t k = len - 1; k >= 0; --k) {  // backward: at most r ahead
          if (near[static_cast<std::size_t>(start + k * st)]) next_one = k;
          near[static_cast<std::size_t>(start + k * st)] = line[static_cast<std::size_t>(k)] || next_one - k <= r;
        }
      }
  }
  return near;
}

// Calls visit(i, value, inside, touches_other_label) for each non-zero voxel: `inside` when every neighbour inside
// the volume holds the same value, `touches_other_label` when a 6-neighbour holds another non-zero value.
template <typename Visit>
void for_each_foreground_voxel(const LabelImage& image, Visit&& visit) {
  const std::int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  std::size_t i = 0;
  for (std::int64_t z = 0; z < nz; ++z)
    for (std::int64_t y = 0; y < ny; ++y)
      for (std::int64_t x = 0; x < nx; ++x, ++i) {
        const std::uint32_t v = image.labels[i];
        if (v == 0) continue;
        bool inside = true, other = false;
        auto look = [&](std::size_t j) {
          const std::uint32_t u = image.labels[j];
          if (u != v) {
            inside = false;
            other = other || u != 0;
          }
        };
        if (x > 0) look(i - 1);
        if (x + 1 < nx) look(i + 1);
        if (y > 0) look(i - static_cast<std::size_t>(nx));
        if (y + 1 < ny) look(i + static_cast<std::size_t>(nx));
        if (z > 0) look(i - static_cast<std::size_t>(nx * ny));
        if (z + 1 < nz) look(i + static_cast<std::size_t>(nx * ny));
        visit(i, v, inside, other);
      }
}

struct GreyStats {
  std::int64_t voxels = 0, in_shell = 0, in_plateau = 0;  // voxels of the values other than the maximum
};

GreyStats grey_stats(const LabelImage& image, std::uint32_t max_value) {
  const std::vector<std::uint8_t> near = near_value(image, max_value, kShellRadius);
  GreyStats g;
  for_each_foreground_voxel(image, [&](std::size_t i, std::uint32_t v, bool inside, bool) {
    if (v == max_value) return;
    ++g.voxels;
    g.in_shell += near[i];
    g.in_plateau += inside;
  });
  return g;
}

// Labels with no inside voxel that touch another label: grey levels of a boundary read as labels.
std::string sliver_warning(const LabelImage& image) {
  struct Flags {
    bool inside = false, touches = false;
  };
  std::unordered_map<std::uint32_t, Flags> labels;
  std::uint32_t last = 0;
  Flags* f = nullptr;
  for_each_foreground_voxel(image, [&](std::size_t, std::uint32_t v, bool inside, bool other) {
    if (f == nullptr || v != last) f = &labels[v], last = v;
    f->inside = f->inside || inside;
    f->touches = f->touches || other;
  });
  std::int64_t slivers = 0;
  for (const auto& [v, fl] : labels) slivers += !fl.inside && fl.touches;
  const auto n = static_cast<std::int64_t>(labels.size());
  if (n < 2 || 2 * slivers <= n) return {};
  return fmt("%.0f of the %.0f labels are thin boundary slivers (no voxel inside them, lying against another label): "
             "this looks like a mask with soft edges or a probability map read as labels; if so, use "
             "--objects components --threshold T (HTTP: objects=components&threshold=T), e.g. T = half the largest value",
             static_cast<double>(slivers), static_cast<double>(n));
}

[[noreturn]] void bad_threshold(const std::string& message, double value) {
  throw InvalidInputError("invalid_parameter", message, {{"parameter", std::string("threshold")}, {"value", value}});
}

}  // namespace

InputDecision decide_input(const LabelImage& image, ObjectMode mode, std::optional<double> threshold) {
  const bool floats = image.probability_scale > 0;
  if (threshold) {
    if (!(std::isfinite(*threshold) && *threshold > 0))
      bad_threshold("threshold must be a number above 0 (foreground: values at or above it), not " +
                        value_text(*threshold), *threshold);
    if (floats && *threshold > 1)
      bad_threshold("threshold " + value_text(*threshold) + " is above 1, the largest value of a probability map",
                    *threshold);
    if (mode == ObjectMode::Labels)
      bad_threshold("a threshold applies to a mask or a probability map (objects auto or components), not to labels",
                    *threshold);
  }
  if (floats && mode == ObjectMode::Labels)
    throw InvalidInputError("invalid_parameter",
                            "the volume holds floats in [0, 1] that are not integers (a probability map), which has "
                            "no labels: use objects auto or components (with a threshold)",
                            {{"parameter", std::string("objects")}});

  // What the values look like.
  InputDecision d;
  double half_max = 0;
  if (floats) {
    d.kind = InputKind::ProbabilityMap;
    half_max = 0.5;
    d.why = "floats in [0, 1] that are not all integers: a probability map";
  } else {
    const ValueStats s = value_stats(image);
    const auto distinct = static_cast<double>(s.counts.size());
    const double nonzero = static_cast<double>(s.voxels - s.zeros);
    half_max = 0.5 * s.max_value;
    if (s.counts.empty()) {
      d.kind = InputKind::Mask;
      d.why = "no non-zero voxel";
    } else if (s.counts.size() == 1) {
      d.kind = InputKind::Mask;
      d.why = "every non-zero voxel holds " + value_text(s.max_value) + " (" + value_text(nonzero) +
              " voxels): a mask";
    } else {
      GreyStats g;
      const bool type_max = s.max_value == 255 || s.max_value == 65535;
      // Only a maximum that is the most frequent value (soft mask) or the type's (probability map) can qualify:
      // instance labels skip the measurement.
      const bool greys_measured = !s.capped && s.counts.size() >= 3 && (s.top_value == s.max_value || type_max);
      const bool max_dominates = greys_measured && s.top_value == s.max_value;
      if (greys_measured) g = grey_stats(image, s.max_value);
      const double greys = static_cast<double>(g.voxels);
      const double shell = greys > 0 ? static_cast<double>(g.in_shell) / greys : 0;
      const double plateau = greys > 0 ? static_cast<double>(g.in_plateau) / greys : 1;
      const double zero_and_max = static_cast<double>(s.zeros + s.at_max) / static_cast<double>(s.voxels);
      const std::string figures =
          value_text(s.max_value) + " is the largest" + (max_dominates ? " and most frequent" : "") +
          " non-zero value (" + value_text(static_cast<double>(s.at_max)) + " voxels); the " + value_text(distinct - 1) +
          " other values (" + value_text(greys) + " voxels) lie " + fmt("%.1f", 100 * shell) + " % within " +
          std::to_string(kShellRadius) + " voxels of it and " + fmt("%.1f", 100 * plateau) +
          " % inside a plateau of their own value";
      if (max_dominates && shell >= kShellShare && plateau < kPlateauShare) {
        d.kind = InputKind::SoftMask;
        d.why = figures + ": a mask with interpolated edges";
      } else if (greys_measured && type_max && zero_and_max >= kZeroAndMaxShare && plateau < kPlateauShare) {
        d.kind = InputKind::ProbabilityMap;
        d.why = figures + fmt("; 0 and %.0f hold %.1f %% of the voxels: a probability map", s.max_value,
                              100 * zero_and_max);
      } else {
        d.kind = InputKind::Labels;
        d.why = s.capped ? "more than " + value_text(static_cast<double>(kMaxDistinctTracked)) + " distinct values: labels"
                : !greys_measured ? value_text(distinct) + " distinct non-zero values, the largest (" +
                                        value_text(s.max_value) + ") neither the most frequent nor 255 / 65535: labels"
                                  : figures + ": labels";
        if (!s.capped) {
          std::string w = sliver_warning(image);
          if (!w.empty()) d.warnings.push_back(std::move(w));
        }
      }
    }
  }

  // How objects are found.
  const bool soft = d.kind == InputKind::SoftMask || d.kind == InputKind::ProbabilityMap;
  if (mode == ObjectMode::Labels) {
    d.mode = ObjectMode::Labels;
    d.why += "; objects=labels set by the caller: each value is one object";
    if (soft)
      d.warnings.push_back(std::string("the values look like a ") + to_string(d.kind) +
                           ": read as labels, each grey level becomes an object; use --objects auto, or components "
                           "--threshold T (HTTP: objects=components&threshold=T)");
  } else if (threshold) {
    d.mode = ObjectMode::Components;
    d.threshold = threshold;
    d.why += "; thresholded at " + value_text(*threshold) + " (set by the caller), then 6-connected components";
  } else if (soft) {
    d.mode = ObjectMode::Components;
    d.threshold = half_max;
    d.why += "; thresholded at half its maximum, " + value_text(half_max) + ", then 6-connected components";
  } else if (mode == ObjectMode::Components || d.kind == InputKind::Mask) {
    d.mode = ObjectMode::Components;
    d.why += mode == ObjectMode::Components ? "; objects=components set by the caller: 6-connected components of the non-zero voxels"
                                            : "; objects are its 6-connected components";
  } else {
    d.mode = ObjectMode::Labels;
    d.why += "; each value is one object";
  }
  return d;
}

std::uint32_t foreground_floor(const LabelImage& image, const InputDecision& decision) {
  if (!decision.threshold) return 1;
  const double t = image.probability_scale > 0 ? *decision.threshold * image.probability_scale : *decision.threshold;
  const double floor = std::max(1.0, std::ceil(t));
  return floor >= 4294967295.0 ? 4294967295u : static_cast<std::uint32_t>(floor);
}

}  // namespace wish::volume
