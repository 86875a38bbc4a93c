#include "core/volume/voxel_topology.hpp"

#include <vector>

namespace wish::volume {

const std::array<std::array<int, 3>, 14>& link_offsets() {
  static const std::array<std::array<int, 3>, 14> offsets = [] {
    std::array<std::array<int, 3>, 14> o{};
    for (std::size_t k = 0; k < 7; ++k) {
      o[k] = kuhn_offsets()[k];
      o[k + 7] = {-o[k][0], -o[k][1], -o[k][2]};
    }
    return o;
  }();
  return offsets;
}

namespace {

// Whether two link points are joined by an edge of the triangulation (their difference is a 14-neighbour offset).
bool adjacent(const std::array<int, 3>& a, const std::array<int, 3>& b) {
  const std::array<int, 3> d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  for (const auto& o : link_offsets())
    if (o == d) return true;
  return false;
}

// Connected components (along link edges) of the link points whose bit in `mask` is set; 0 for none.
int link_components(std::uint32_t mask, const std::array<std::uint16_t, 14>& adjacency) {
  int count = 0;
  std::uint32_t seen = 0;
  for (int start = 0; start < 14; ++start) {
    if (!(mask >> start & 1u) || (seen >> start & 1u)) continue;
    ++count;
    std::uint32_t frontier = 1u << start;
    seen |= frontier;
    while (frontier) {
      std::uint32_t next = 0;
      for (int k = 0; k < 14; ++k)
        if (frontier >> k & 1u) next |= adjacency[static_cast<std::size_t>(k)];
      next &= mask & ~seen;
      seen |= next;
      frontier = next;
    }
  }
  return count;
}

const std::vector<bool>& simple_table() {
  static const std::vector<bool> table = [] {
    std::array<std::uint16_t, 14> adjacency{};
    const auto& o = link_offsets();
    for (std::size_t a = 0; a < 14; ++a)
      for (std::size_t b = 0; b < 14; ++b)
        if (a != b && adjacent(o[a], o[b])) adjacency[a] = static_cast<std::uint16_t>(adjacency[a] | (1u << b));
    std::vector<bool> t(1u << 14);
    const std::uint32_t all = (1u << 14) - 1;
    for (std::uint32_t m = 0; m <= all; ++m)
      t[m] = link_components(m, adjacency) == 1 && link_components(all & ~m, adjacency) == 1;
    return t;
  }();
  return table;
}

// χ of the foreground's full subcomplex. Every simplex of the Kuhn triangulation is a chain p < p + a < p + c < ...
// of corners of the unit cube at p (offsets as corner bits x = 1, y = 2, z = 4, each a subset of the next), counted
// once from its lowest point p: 7 edges (p, p + c), 12 triangles (p, p + a, p + c) with a a proper non-empty subset
// of c, and 6 tetrahedra (p, p + a, p + b, p + 111) with |a| = 1, |b| = 2.
std::int64_t euler_characteristic(const BinaryVolume& v) {
  struct Tri { int a, c; };
  struct Tet { int a, b; };
  std::vector<Tri> tris;
  std::vector<Tet> tets;
  for (int c = 1; c < 8; ++c)
    for (int a = 1; a < c; ++a)
      if ((a & c) == a) tris.push_back({a, c});
  for (int a : {1, 2, 4})
    for (int b : {3, 5, 6})
      if ((a & b) == a) tets.push_back({a, b});
  const int nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
  std::int64_t chi = 0;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        if (!v.at(x, y, z)) continue;
        bool corner[8];
        for (int c = 0; c < 8; ++c) {
          const int qx = x + (c & 1), qy = y + (c >> 1 & 1), qz = z + (c >> 2 & 1);
          corner[c] = qx < nx && qy < ny && qz < nz && v.at(qx, qy, qz);
        }
        std::int64_t local = 1;
        for (int c = 1; c < 8; ++c) local -= corner[c];
        for (const Tri& t : tris) local += corner[t.a] && corner[t.c];
        for (const Tet& t : tets) local -= corner[t.a] && corner[t.b] && corner[7];
        chi += local;
      }
  return chi;
}

}  // namespace

bool is_simple_point(std::uint32_t neighbours_in_set) { return simple_table()[neighbours_in_set & ((1u << 14) - 1)]; }

VoxelTopology voxel_topology(const BinaryVolume& v) {
  VoxelTopology t;
  std::vector<int> id;
  t.components = static_cast<std::int64_t>(components(v, 1, id).size());
  const auto background = components(v, 0, id);
  const std::vector<bool> outside = touching_border(v, id, background.size());
  for (bool o : outside) t.cavities += !o;
  t.euler = euler_characteristic(v);
  t.handles = t.components + t.cavities - t.euler;
  return t;
}

}  // namespace wish::volume
