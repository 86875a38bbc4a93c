#include "core/volume/label_objects.hpp"

#include <algorithm>
#include <unordered_map>

#include "core/common/errors.hpp"

namespace wish::volume {

const char* to_string(ObjectMode mode) {
  switch (mode) {
    case ObjectMode::Auto: return "auto";
    case ObjectMode::Labels: return "labels";
    case ObjectMode::Components: return "components";
  }
  return "?";
}

namespace {

struct Accumulator {
  std::int64_t count = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::array<std::int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{-1, -1, -1};
  void add(std::int64_t x, std::int64_t y, std::int64_t z) {
    ++count;
    sum += Eigen::Vector3d(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z));
    const std::int64_t p[3] = {x, y, z};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
};

[[noreturn]] void too_many(std::int64_t allowed) {
  throw LimitExceededError("the volume holds more than " + std::to_string(allowed) + " objects",
                           {{"limit", std::string("max_objects")}, {"value", allowed + 1}, {"allowed", allowed}});
}

// 6-connected components of the foreground voxels (value >= floor), numbered 1.. in scan order; fills `acc`.
std::vector<std::uint32_t> label_components(const LabelImage& image, std::uint32_t floor, std::int64_t max_objects,
                                            std::vector<Accumulator>& acc) {
  const std::int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
  std::vector<std::uint32_t> id(image.labels.size(), 0);
  std::vector<std::int64_t> stack;
  for (std::int64_t start = 0; start < static_cast<std::int64_t>(image.labels.size()); ++start) {
    if (image.labels[static_cast<std::size_t>(start)] < floor || id[static_cast<std::size_t>(start)] != 0) continue;
    if (static_cast<std::int64_t>(acc.size()) >= max_objects) too_many(max_objects);
    acc.emplace_back();
    const auto c = static_cast<std::uint32_t>(acc.size());
    id[static_cast<std::size_t>(start)] = c;
    stack.push_back(start);
    while (!stack.empty()) {
      const std::int64_t i = stack.back();
      stack.pop_back();
      const std::int64_t x = i % nx, y = (i / nx) % ny, z = i / (nx * ny);
      acc.back().add(x, y, z);
      auto visit = [&](std::int64_t j) {
        if (image.labels[static_cast<std::size_t>(j)] >= floor && id[static_cast<std::size_t>(j)] == 0) {
          id[static_cast<std::size_t>(j)] = c;
          stack.push_back(j);
        }
      };
      if (x > 0) visit(i - 1);
      if (x + 1 < nx) visit(i + 1);
      if (y > 0) visit(i - nx);
      if (y + 1 < ny) visit(i + nx);
      if (z > 0) visit(i - nx * ny);
      if (z + 1 < nz) visit(i + nx * ny);
    }
  }
  return id;
}

}  // namespace

ObjectSet find_objects(const LabelImage& image, const ObjectOptions& options) {
  if (image.labels.size() != static_cast<std::size_t>(image.voxel_count()))
    throw InvalidInputError("invalid_volume", "label image holds " + std::to_string(image.labels.size()) +
                                                  " values for " + std::to_string(image.voxel_count()) + " voxels");
  ObjectSet set;
  set.input = decide_input(image, options.mode, options.threshold);
  set.mode = set.input.mode;
  std::vector<Accumulator> acc;
  std::vector<std::uint32_t> ids;
  if (set.mode == ObjectMode::Components) {
    set.component_ids = label_components(image, foreground_floor(image, set.input), options.max_objects, acc);
    for (std::size_t c = 0; c < acc.size(); ++c) ids.push_back(static_cast<std::uint32_t>(c + 1));
  } else {
    std::unordered_map<std::uint32_t, std::size_t> slot;
    std::uint32_t last = 0;
    std::size_t last_slot = 0;
    const std::int64_t nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
    std::size_t i = 0;
    for (std::int64_t z = 0; z < nz; ++z)
      for (std::int64_t y = 0; y < ny; ++y)
        for (std::int64_t x = 0; x < nx; ++x, ++i) {
          const std::uint32_t v = image.labels[i];
          if (v == 0) continue;
          if (v != last || acc.empty()) {
            auto [it, inserted] = slot.try_emplace(v, acc.size());
            if (inserted) {
              if (static_cast<std::int64_t>(acc.size()) >= options.max_objects) too_many(options.max_objects);
              acc.emplace_back();
              ids.push_back(v);
            }
            last = v;
            last_slot = it->second;
          }
          acc[last_slot].add(x, y, z);
        }
  }
  set.found = static_cast<std::int64_t>(acc.size());
  for (std::size_t k = 0; k < acc.size(); ++k) {
    const Accumulator& a = acc[k];
    VolumeObject o;
    o.id = ids[k];
    o.voxel_count = a.count;
    o.centroid = (a.sum / static_cast<double>(a.count)).cwiseProduct(image.spacing);
    o.bbox_min = a.lo;
    o.bbox_max = a.hi;
    for (int d = 0; d < 3; ++d) o.truncated = o.truncated || a.lo[d] == 0 || a.hi[d] == image.dims[d] - 1;
    if (!options.label_ids.empty() &&
        std::find(options.label_ids.begin(), options.label_ids.end(), o.id) == options.label_ids.end()) {
      ++set.dropped_not_selected;
      continue;
    }
    if (o.voxel_count < options.min_voxels) {
      ++set.dropped_small;
      continue;
    }
    if (o.truncated && options.drop_truncated) {
      ++set.dropped_truncated;
      continue;
    }
    set.objects.push_back(o);
  }
  std::sort(set.objects.begin(), set.objects.end(), [](const VolumeObject& a, const VolumeObject& b) { return a.id < b.id; });
  return set;
}

}  // namespace wish::volume
