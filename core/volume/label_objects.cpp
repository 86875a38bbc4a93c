#include "core/volume/label_objects.hpp"

#include <algorithm>
#include <unordered_map>

#include "core/common/errors.hpp"

namespace wish::volume {

const char* to_string(DropReason reason) {
  switch (reason) {
    case DropReason::NotSelected: return "not_selected";
    case DropReason::Speck: return "speck";
    case DropReason::Small: return "small";
    case DropReason::Truncated: return "truncated";
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
  void merge(const Accumulator& o) {
    count += o.count;
    sum += o.sum;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], o.lo[k]);
      hi[k] = std::max(hi[k], o.hi[k]);
    }
  }
};

Eigen::Vector3d centroid_of(const Accumulator& a, const LabelImage& image) {
  return (a.sum / static_cast<double>(a.count)).cwiseProduct(image.spacing);
}

// Mask components near a dominant one become its fragments: their voxels take its id, their accumulators merge into
// its, and they leave `ids` / `acc`. Returns the pieces merged; `main_id` is set to the dominant component's id.
std::vector<ObjectPiece> merge_fragments(const LabelImage& image, int gap, std::vector<std::uint32_t>& component_ids,
                                         std::vector<Accumulator>& acc, std::vector<std::uint32_t>& ids,
                                         std::uint32_t& main_id) {
  if (gap < 0 || acc.size() < 2) return {};
  std::int64_t total = 0;
  std::size_t main = 0;
  for (std::size_t c = 0; c < acc.size(); ++c) {
    total += acc[c].count;
    if (acc[c].count > acc[main].count) main = c;
  }
  if (static_cast<double>(acc[main].count) < kDominantShare * static_cast<double>(total)) return {};
  std::vector<std::array<std::int64_t, 3>> lo(acc.size()), hi(acc.size());
  for (std::size_t c = 0; c < acc.size(); ++c) lo[c] = acc[c].lo, hi[c] = acc[c].hi;
  main_id = static_cast<std::uint32_t>(main + 1);
  const std::vector<int> gaps = gaps_to_component(image.dims, component_ids, lo, hi, main_id, gap);
  std::vector<ObjectPiece> pieces;
  std::vector<bool> merged(acc.size(), false);
  for (std::size_t c = 0; c < acc.size(); ++c) {
    if (gaps[c] < 0) continue;
    merged[c] = true;
    pieces.push_back({static_cast<std::uint32_t>(c + 1), acc[c].count, centroid_of(acc[c], image), gaps[c]});
    acc[main].merge(acc[c]);
  }
  if (pieces.empty()) return pieces;
  for (auto& id : component_ids)
    if (id != 0 && merged[id - 1]) id = main_id;
  std::vector<Accumulator> kept_acc;
  std::vector<std::uint32_t> kept_ids;
  for (std::size_t c = 0; c < acc.size(); ++c)
    if (!merged[c]) kept_acc.push_back(acc[c]), kept_ids.push_back(ids[c]);
  acc = std::move(kept_acc);
  ids = std::move(kept_ids);
  return pieces;
}

std::string count_text(std::int64_t n) { return std::to_string(n) + (n == 1 ? " voxel" : " voxels"); }

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
  std::vector<ObjectPiece> fragments;
  std::uint32_t main_id = 0;
  if (set.mode == ObjectMode::Components)
    fragments = merge_fragments(image, options.fragment_gap, set.component_ids, acc, ids, main_id);
  set.fragments_merged = static_cast<std::int64_t>(fragments.size());
  set.found = static_cast<std::int64_t>(acc.size());
  if (!options.min_voxels) {
    std::vector<std::int64_t> counts;
    for (const Accumulator& a : acc) counts.push_back(a.count);
    set.specks = speck_rule(counts);
  }
  for (std::size_t k = 0; k < acc.size(); ++k) {
    const Accumulator& a = acc[k];
    VolumeObject o;
    o.id = ids[k];
    o.voxel_count = a.count;
    o.centroid = centroid_of(a, image);
    o.bbox_min = a.lo;
    o.bbox_max = a.hi;
    for (int d = 0; d < 3; ++d) o.truncated = o.truncated || a.lo[d] == 0 || a.hi[d] == image.dims[d] - 1;
    if (o.id == main_id) o.fragments = fragments;
    auto drop = [&](DropReason reason, std::int64_t& counter, std::string why) {
      ++counter;
      set.dropped.push_back({std::move(o), reason, std::move(why)});
    };
    if (!options.label_ids.empty() &&
        std::find(options.label_ids.begin(), options.label_ids.end(), o.id) == options.label_ids.end()) {
      drop(DropReason::NotSelected, set.dropped_not_selected, "not among the selected label ids");
    } else if (options.min_voxels && o.voxel_count < *options.min_voxels) {
      drop(DropReason::Small, set.dropped_small,
           count_text(o.voxel_count) + ", under min_voxels " + std::to_string(*options.min_voxels));
    } else if (!options.min_voxels && o.voxel_count < set.specks.below) {
      drop(DropReason::Speck, set.dropped_specks,
           count_text(o.voxel_count) + ", under " + std::to_string(set.specks.below) +
               " (the volume's typical object has " + count_text(set.specks.typical_voxels) +
               "; min_voxels sets the bound)");
    } else if (o.truncated && options.drop_truncated) {
      drop(DropReason::Truncated, set.dropped_truncated, "touches the volume border (drop_truncated)");
    } else {
      set.objects.push_back(std::move(o));
    }
  }
  std::sort(set.dropped.begin(), set.dropped.end(),
            [](const DroppedObject& a, const DroppedObject& b) { return a.object.id < b.object.id; });
  std::sort(set.objects.begin(), set.objects.end(), [](const VolumeObject& a, const VolumeObject& b) { return a.id < b.id; });
  return set;
}

}  // namespace wish::volume
