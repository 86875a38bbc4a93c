#include "core/volume/surface_topology.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <vector>

#include <Eigen/Geometry>

namespace wish::volume {

std::string SurfaceTopology::describe() const {
  return "V=" + std::to_string(vertices) + " E=" + std::to_string(edges) + " F=" + std::to_string(faces) +
         " chi=" + std::to_string(euler) + " components=" + std::to_string(components) +
         " bad_edges=" + std::to_string(bad_edges) + " nonmanifold_vertices=" + std::to_string(nonmanifold_vertices) +
         " degenerate=" + std::to_string(degenerate_faces) + " volume=" + std::to_string(signed_volume);
}

SurfaceTopology analyze_surface(const Mesh& mesh) {
  SurfaceTopology t;
  const auto& F = mesh.faces;
  const auto& V = mesh.vertices;
  t.vertices = V.rows();
  t.faces = F.rows();
  // Directed edge counts.
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++directed[{F(f, k), F(f, (k + 1) % 3)}];
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2) || (b - a).cross(c - a).norm() <= 1e-14)
      ++t.degenerate_faces;
    t.signed_volume += a.dot(b.cross(c)) / 6;
  }
  std::int64_t undirected = 0;
  for (const auto& [e, n] : directed) {
    const auto it = directed.find({e.second, e.first});
    const int back = it == directed.end() ? 0 : it->second;
    if (e.first < e.second || it == directed.end()) ++undirected;
    if (n != 1 || back != 1) ++t.bad_edges;
  }
  t.edges = undirected;
  t.euler = t.vertices - t.edges + t.faces;
  // Components (union-find over faces' vertices) and vertex fans.
  std::vector<int> parent(static_cast<std::size_t>(V.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<std::vector<Eigen::Index>> incident(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      parent[find(F(f, k))] = find(F(f, (k + 1) % 3));
      incident[F(f, k)].push_back(f);
    }
  std::vector<bool> root(parent.size(), false);
  for (int i = 0; i < static_cast<int>(parent.size()); ++i)
    if (!incident[i].empty()) root[find(i)] = true;
  t.components = std::count(root.begin(), root.end(), true);
  // A manifold vertex's faces form one cycle: walking "next face around v" from any face returns after all.
  for (int v = 0; v < static_cast<int>(incident.size()); ++v) {
    const auto& inc = incident[v];
    if (inc.empty()) continue;
    std::map<int, Eigen::Index> by_first;  // face (v, a, b) keyed by a
    for (Eigen::Index f : inc) {
      int k = 0;
      while (F(f, k) != v) ++k;
      by_first[F(f, (k + 1) % 3)] = f;
    }
    Eigen::Index f = inc.front();
    std::size_t steps = 0;
    do {
      int k = 0;
      while (F(f, k) != v) ++k;
      const auto it = by_first.find(F(f, (k + 2) % 3));
      if (it == by_first.end()) break;
      f = it->second;
      ++steps;
    } while (f != inc.front() && steps <= inc.size());
    if (f != inc.front() || steps != inc.size()) ++t.nonmanifold_vertices;
  }
  return t;
}

}  // namespace wish::volume
