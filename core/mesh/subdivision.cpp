#include "core/mesh/subdivision.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/common/errors.hpp"

namespace wish {

Mesh subdivide_midpoint(const Mesh& mesh, int levels) {
  if (levels < 0 || levels > 6)
    throw InvalidInputError("invalid_parameter", "subdivision levels " + std::to_string(levels) + " outside [0, 6]",
                            {{"levels", std::int64_t{levels}}});
  std::vector<Eigen::Vector3d> v(static_cast<size_t>(mesh.vertex_count()));
  for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i) v[static_cast<size_t>(i)] = mesh.vertices.row(i);
  std::vector<std::array<int, 3>> f(static_cast<size_t>(mesh.face_count()));
  for (Eigen::Index i = 0; i < mesh.face_count(); ++i)
    f[static_cast<size_t>(i)] = {mesh.faces(i, 0), mesh.faces(i, 1), mesh.faces(i, 2)};
  for (int level = 0; level < levels; ++level) {
    std::unordered_map<std::uint64_t, int> midpoint;  // edge (min, max) -> its new vertex
    const auto mid = [&](int a, int b) {
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b));
      if (const auto it = midpoint.find(key); it != midpoint.end()) return it->second;
      v.push_back(0.5 * (v[static_cast<size_t>(a)] + v[static_cast<size_t>(b)]));
      const int id = static_cast<int>(v.size()) - 1;
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(f.size() * 4);
    for (const auto& t : f) {
      const int a = mid(t[0], t[1]), b = mid(t[1], t[2]), c = mid(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    f.swap(next);
  }
  Mesh out;
  out.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (size_t i = 0; i < v.size(); ++i) out.vertices.row(static_cast<Eigen::Index>(i)) = v[i];
  out.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i)
    out.faces.row(static_cast<Eigen::Index>(i)) << f[i][0], f[i][1], f[i][2];
  return out;
}

}  // namespace wish
