#include "core/volume/topology_repair.hpp"

#include <algorithm>
#include <cstdio>
#include <queue>
#include <utility>
#include <vector>

#include "core/volume/distance_transform.hpp"
#include "core/volume/voxel_topology.hpp"

namespace wish::volume {

const char* TopologyRepairFigures::method() const {
  if (removed > 0 && added > 0) return "cut_and_fill";
  if (removed > 0) return "cut";
  if (added > 0) return "fill";
  return "none";
}

std::string TopologyRepairFigures::describe() const {
  std::string out;
  char buf[160];
  if (cuts > 0) {
    std::snprintf(buf, sizeof buf, "cut %d handle%s (-%lld voxels)", cuts, cuts == 1 ? "" : "s",
                  static_cast<long long>(removed));
    out += buf;
  }
  if (fills > 0) {
    std::snprintf(buf, sizeof buf, "%sfilled %d tunnel%s (+%lld voxels)", out.empty() ? "" : ", ", fills,
                  fills == 1 ? "" : "s", static_cast<long long>(added));
    out += buf;
  }
  std::snprintf(buf, sizeof buf, "%sgenus %d -> 0, volume change %.2f %%", out.empty() ? "" : ": ", genus_before,
                100 * volume_change());
  return out + buf;
}

namespace {

std::int64_t count(const BinaryVolume& v, std::uint8_t value) {
  return static_cast<std::int64_t>(std::count(v.labels.begin(), v.labels.end(), value));
}

// Linear index offsets of the 14 link neighbours.
std::array<std::int64_t, 14> neighbour_steps(const BinaryVolume& v) {
  std::array<std::int64_t, 14> steps{};
  const auto& o = link_offsets();
  for (std::size_t k = 0; k < 14; ++k)
    steps[k] = o[k][0] + static_cast<std::int64_t>(v.dims[0]) * (o[k][1] + static_cast<std::int64_t>(v.dims[1]) * o[k][2]);
  return steps;
}

bool on_border(const BinaryVolume& v, std::size_t i) {
  const auto nx = static_cast<std::size_t>(v.dims[0]), ny = static_cast<std::size_t>(v.dims[1]);
  const std::size_t x = i % nx, y = (i / nx) % ny, z = i / (nx * ny);
  return x == 0 || y == 0 || z == 0 || x + 1 == nx || y + 1 == ny || z + 1 == static_cast<std::size_t>(v.dims[2]);
}

// Grows `grown` (1 = in the set) by simple points among the voxels where `allowed` holds, largest `priority` first.
// The voxels already in the set are the start; no allowed voxel lies on the border layer.
void grow_by_simple_points(const BinaryVolume& v, const std::vector<double>& priority,
                           const std::vector<std::uint8_t>& allowed, std::vector<std::uint8_t>& grown) {
  const auto steps = neighbour_steps(v);
  // Largest priority first; among equal priorities (a tunnel of constant width) the first queued, so that fronts
  // entering a tunnel from both ends advance alike and meet, leaving the plug in its middle.
  struct Entry {
    double priority;
    std::int64_t order, index;
    bool operator<(const Entry& o) const { return priority < o.priority || (priority == o.priority && order > o.order); }
  };
  std::priority_queue<Entry> queue;
  std::int64_t queued = 0;
  auto push = [&](std::int64_t j) { queue.push({priority[static_cast<std::size_t>(j)], queued++, j}); };
  auto push_neighbours = [&](std::int64_t i) {
    for (const std::int64_t s : steps) {
      const std::int64_t j = i + s;
      if (allowed[static_cast<std::size_t>(j)] && !grown[static_cast<std::size_t>(j)]) push(j);
    }
  };
  // The first candidates: those next to the start set (found from the candidate's side, whose neighbours all lie
  // inside the grid).
  for (std::size_t i = 0; i < grown.size(); ++i) {
    if (!allowed[i] || grown[i]) continue;
    for (const std::int64_t s : steps)
      if (grown[static_cast<std::size_t>(static_cast<std::int64_t>(i) + s)]) {
        push(static_cast<std::int64_t>(i));
        break;
      }
  }
  while (!queue.empty()) {
    const std::int64_t i = queue.top().index;
    queue.pop();
    if (grown[static_cast<std::size_t>(i)]) continue;
    std::uint32_t mask = 0;
    for (std::size_t k = 0; k < 14; ++k) mask |= static_cast<std::uint32_t>(grown[static_cast<std::size_t>(i + steps[k])]) << k;
    if (!is_simple_point(mask)) continue;  // tried again when one of its neighbours joins
    grown[static_cast<std::size_t>(i)] = 1;
    push_neighbours(i);
  }
}

// The object voxels a ball grown inside the object cannot take (the cuts).
std::vector<std::uint8_t> cut_voxels(const BinaryVolume& object) {
  const std::vector<double> depth = squared_distance_to(object, 0);
  std::size_t seed = 0;
  for (std::size_t i = 0; i < depth.size(); ++i)
    if (object.labels[i] && depth[i] > depth[seed]) seed = i;
  std::vector<std::uint8_t> grown(object.labels.size(), 0);
  grown[seed] = 1;
  grow_by_simple_points(object, depth, object.labels, grown);
  std::vector<std::uint8_t> cut(object.labels.size(), 0);
  for (std::size_t i = 0; i < cut.size(); ++i) cut[i] = object.labels[i] && !grown[i];
  return cut;
}

// The background voxels the outside, grown inward, cannot take (the plugs).
std::vector<std::uint8_t> plug_voxels(const BinaryVolume& object) {
  const std::vector<double> far = squared_distance_to(object, 1);
  std::vector<std::uint8_t> grown(object.labels.size(), 0), allowed(object.labels.size(), 0);
  for (std::size_t i = 0; i < grown.size(); ++i) {
    if (object.labels[i]) continue;
    if (on_border(object, i)) grown[i] = 1;
    else allowed[i] = 1;
  }
  grow_by_simple_points(object, far, allowed, grown);
  std::vector<std::uint8_t> plug(object.labels.size(), 0);
  for (std::size_t i = 0; i < plug.size(); ++i) plug[i] = allowed[i] && !grown[i];
  return plug;
}

struct Group {
  std::vector<std::size_t> voxels;
  bool cut = false;  // else a plug
};

// The 14-connected groups of the marked voxels.
void add_groups(const BinaryVolume& shape, const std::vector<std::uint8_t>& marked, bool cut, std::vector<Group>& out) {
  BinaryVolume v;
  v.dims = shape.dims;
  v.labels = marked;
  std::vector<int> id;
  const auto sizes = components(v, 1, id);
  const std::size_t first = out.size();
  out.resize(first + sizes.size());
  for (std::size_t g = 0; g < sizes.size(); ++g) {
    out[first + g].cut = cut;
    out[first + g].voxels.reserve(sizes[g]);
  }
  for (std::size_t i = 0; i < id.size(); ++i)
    if (id[i] >= 0) out[first + static_cast<std::size_t>(id[i])].voxels.push_back(i);
}

}  // namespace

TopologyRepair remove_handles(const BinaryVolume& object) {
  TopologyRepair r;
  TopologyRepairFigures& f = r.figures;
  f.voxels_before = count(object, 1);
  VoxelTopology current = voxel_topology(object);
  f.genus_before = static_cast<int>(current.handles);
  r.result = object;
  if (current.handles <= 0) return r;

  const std::vector<std::uint8_t> cut = cut_voxels(object), plug = plug_voxels(object);
  f.cut_every_handle = static_cast<std::int64_t>(std::count(cut.begin(), cut.end(), 1));
  f.fill_every_tunnel = static_cast<std::int64_t>(std::count(plug.begin(), plug.end(), 1));

  // Per handle: the groups smallest first, each kept when it lowers the genus without splitting the object or
  // enclosing a cavity.
  std::vector<Group> groups;
  add_groups(object, cut, true, groups);
  add_groups(object, plug, false, groups);
  std::stable_sort(groups.begin(), groups.end(),
                   [](const Group& a, const Group& b) { return a.voxels.size() < b.voxels.size(); });
  BinaryVolume mixed = object;
  std::int64_t removed = 0, added = 0;
  int cuts = 0, fills = 0;
  for (const Group& g : groups) {
    if (current.handles == 0) break;
    BinaryVolume trial = mixed;
    for (std::size_t i : g.voxels) trial.labels[i] = g.cut ? 0 : 1;
    const VoxelTopology t = voxel_topology(trial);
    if (t.components != 1 || t.cavities != 0 || t.handles >= current.handles) continue;
    mixed = std::move(trial);
    current = t;
    (g.cut ? removed : added) += static_cast<std::int64_t>(g.voxels.size());
    ++(g.cut ? cuts : fills);
  }

  // The least change among the per-handle result (when it reached genus 0) and the two pure repairs.
  const std::int64_t mixed_change = current.handles == 0 ? removed + added : -1;
  const std::int64_t groups_cut = static_cast<std::int64_t>(
      std::count_if(groups.begin(), groups.end(), [](const Group& g) { return g.cut; }));
  const std::int64_t groups_plug = static_cast<std::int64_t>(groups.size()) - groups_cut;
  if (mixed_change >= 0 && mixed_change <= std::min(f.cut_every_handle, f.fill_every_tunnel)) {
    r.result = std::move(mixed);
    f.removed = removed, f.added = added, f.cuts = cuts, f.fills = fills;
  } else if (f.cut_every_handle <= f.fill_every_tunnel) {
    for (std::size_t i = 0; i < cut.size(); ++i)
      if (cut[i]) r.result.labels[i] = 0;
    f.removed = f.cut_every_handle, f.cuts = static_cast<int>(groups_cut);
  } else {
    for (std::size_t i = 0; i < plug.size(); ++i)
      if (plug[i]) r.result.labels[i] = 1;
    f.added = f.fill_every_tunnel, f.fills = static_cast<int>(groups_plug);
  }
  return r;
}

}  // namespace wish::volume
