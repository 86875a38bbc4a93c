#include "core/volume/binary_volume.hpp"

#include <algorithm>

namespace wish::volume {

const std::array<std::array<int, 3>, 7>& kuhn_offsets() {
  static const std::array<std::array<int, 3>, 7> offsets = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}};
  return offsets;
}

std::vector<std::size_t> components(const BinaryVolume& v, std::uint8_t value, std::vector<int>& id) {
  const int nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
  id.assign(v.labels.size(), -1);
  std::vector<std::size_t> sizes;
  std::vector<std::array<int, 3>> stack;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        if (v.at(x, y, z) != value || id[v.index(x, y, z)] >= 0) continue;
        const int c = static_cast<int>(sizes.size());
        sizes.push_back(0);
        stack.push_back({x, y, z});
        id[v.index(x, y, z)] = c;
        while (!stack.empty()) {
          const auto p = stack.back();
          stack.pop_back();
          ++sizes[c];
          for (const auto& o : kuhn_offsets())
            for (int sign : {1, -1}) {
              const int qx = p[0] + sign * o[0], qy = p[1] + sign * o[1], qz = p[2] + sign * o[2];
              if (qx < 0 || qy < 0 || qz < 0 || qx >= nx || qy >= ny || qz >= nz) continue;
              const std::size_t qi = v.index(qx, qy, qz);
              if (v.labels[qi] != value || id[qi] >= 0) continue;
              id[qi] = c;
              stack.push_back({qx, qy, qz});
            }
        }
      }
  return sizes;
}

std::vector<bool> touching_border(const BinaryVolume& v, const std::vector<int>& id, std::size_t count) {
  std::vector<bool> touches(count, false);
  const int nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        if ((x == 0 || y == 0 || z == 0 || x == nx - 1 || y == ny - 1 || z == nz - 1) && id[v.index(x, y, z)] >= 0)
          touches[static_cast<std::size_t>(id[v.index(x, y, z)])] = true;
  return touches;
}

int keep_largest_component(BinaryVolume& v) {
  std::vector<int> id;
  const auto sizes = components(v, 1, id);
  if (sizes.size() <= 1) return static_cast<int>(sizes.size());
  const int keep = static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  for (std::size_t i = 0; i < v.labels.size(); ++i)
    if (v.labels[i] && id[i] != keep) v.labels[i] = 0;
  return static_cast<int>(sizes.size());
}

int fill_cavities(BinaryVolume& v) {
  std::vector<int> id;
  const auto sizes = components(v, 0, id);
  const std::vector<bool> touches = touching_border(v, id, sizes.size());
  int filled = 0;
  for (std::size_t c = 0; c < sizes.size(); ++c) filled += !touches[c];
  for (std::size_t i = 0; i < v.labels.size(); ++i)
    if (id[i] >= 0 && !touches[id[i]]) v.labels[i] = 1;
  return filled;
}

void clear_border(BinaryVolume& v) {
  const int nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        if (x == 0 || y == 0 || z == 0 || x == nx - 1 || y == ny - 1 || z == nz - 1) v.labels[v.index(x, y, z)] = 0;
}

}  // namespace wish::volume
