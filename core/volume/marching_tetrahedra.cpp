#include "core/volume/marching_tetrahedra.hpp"

#include <unordered_map>

#include <Eigen/Geometry>
#include <vector>

namespace wish::volume {

Mesh marching_tetrahedra(const BinaryVolume& v) {
  const int nx = v.dims[0], ny = v.dims[1], nz = v.dims[2];
  // The 6 Kuhn tetrahedra of a unit cube: 0 -> e_a -> e_a + e_b -> (1,1,1) for each axis permutation (a, b).
  // Corner bit k set means +1 along axis k.
  static const int tets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  std::unordered_map<std::uint64_t, int> edge_vertex;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3i> faces;
  auto grid_index = [&](int x, int y, int z) { return static_cast<std::uint64_t>(v.index(x, y, z)); };
  auto position = [&](int x, int y, int z) { return Eigen::Vector3d(v.origin + v.spacing.cwiseProduct(Eigen::Vector3d(x, y, z))); };
  auto vertex_on = [&](const int* a, const int* b) {
    std::uint64_t ia = grid_index(a[0], a[1], a[2]), ib = grid_index(b[0], b[1], b[2]);
    if (ia > ib) std::swap(ia, ib);
    const std::uint64_t key = ia * 0x100000000ull + ib;  // grids stay far below 2^32 points
    auto [it, inserted] = edge_vertex.try_emplace(key, static_cast<int>(positions.size()));
    if (inserted) positions.push_back(0.5 * (position(a[0], a[1], a[2]) + position(b[0], b[1], b[2])));
    return it->second;
  };
  auto emit = [&](int i, int j, int k, const Eigen::Vector3d& outward) {
    const Eigen::Vector3d n = (positions[j] - positions[i]).cross(positions[k] - positions[i]);
    if (n.dot(outward) >= 0) faces.emplace_back(i, j, k);
    else faces.emplace_back(i, k, j);
  };
  for (int z = 0; z + 1 < nz; ++z)
    for (int y = 0; y + 1 < ny; ++y)
      for (int x = 0; x + 1 < nx; ++x) {
        int corner[8][3];
        int value[8];
        bool any_in = false, any_out = false;
        for (int c = 0; c < 8; ++c) {
          corner[c][0] = x + (c & 1);
          corner[c][1] = y + ((c >> 1) & 1);
          corner[c][2] = z + ((c >> 2) & 1);
          value[c] = v.at(corner[c][0], corner[c][1], corner[c][2]);
          (value[c] ? any_in : any_out) = true;
        }
        if (!any_in || !any_out) continue;
        for (const auto& t : tets) {
          std::vector<int> in, out;
          for (int c : t) (value[c] ? in : out).push_back(c);
          if (in.empty() || out.empty()) continue;
          Eigen::Vector3d cin = Eigen::Vector3d::Zero(), cout = Eigen::Vector3d::Zero();
          for (int c : in) cin += position(corner[c][0], corner[c][1], corner[c][2]) / static_cast<double>(in.size());
          for (int c : out) cout += position(corner[c][0], corner[c][1], corner[c][2]) / static_cast<double>(out.size());
          const Eigen::Vector3d outward = cout - cin;
          if (in.size() == 1 || out.size() == 1) {  // one corner cut off: a triangle
            const int apex = in.size() == 1 ? in[0] : out[0];
            const std::vector<int>& others = in.size() == 1 ? out : in;
            const int a = vertex_on(corner[apex], corner[others[0]]);
            const int b = vertex_on(corner[apex], corner[others[1]]);
            const int c = vertex_on(corner[apex], corner[others[2]]);
            emit(a, b, c, outward);
          } else {  // two and two: a quad through the four crossing edges, in cyclic order
            const int p = vertex_on(corner[in[0]], corner[out[0]]);
            const int q = vertex_on(corner[in[0]], corner[out[1]]);
            const int r = vertex_on(corner[in[1]], corner[out[1]]);
            const int s = vertex_on(corner[in[1]], corner[out[0]]);
            emit(p, q, r, outward);
            emit(p, r, s, outward);
          }
        }
      }
  Mesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t i = 0; i < positions.size(); ++i) mesh.vertices.row(static_cast<Eigen::Index>(i)) = positions[i].transpose();
  mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) mesh.faces.row(static_cast<Eigen::Index>(i)) = faces[i].transpose();
  return mesh;
}

}  // namespace wish::volume
