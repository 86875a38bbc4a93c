#include "core/validation/edge_topology.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace wish::validation_detail {

namespace {

// Union-find with path halving; `touched` lets a caller reset only the entries it used.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(Eigen::Index n) : parent(static_cast<std::size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
      auto& p = parent[static_cast<std::size_t>(x)];
      p = parent[static_cast<std::size_t>(p)];
      x = p;
    }
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
};

}  // namespace

bool is_proper_face(const Eigen::MatrixX3i& faces, Eigen::Index f, Eigen::Index vertex_count) {
  const int a = faces(f, 0), b = faces(f, 1), c = faces(f, 2);
  const auto in_range = [&](int i) { return i >= 0 && i < vertex_count; };
  return in_range(a) && in_range(b) && in_range(c) && a != b && b != c && a != c;
}

EdgeTopology compute_edge_topology(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count) {
  EdgeTopology t;
  std::vector<Eigen::Index> proper;
  proper.reserve(static_cast<std::size_t>(faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    if (is_proper_face(faces, f, vertex_count)) proper.push_back(f);
  t.proper_faces = static_cast<std::int64_t>(proper.size());

  // Half-edges keyed by their undirected edge (min << 32 | max); the low bit of `forward` says a < b.
  struct HalfEdge {
    std::uint64_t key;
    bool forward;
    bool operator<(const HalfEdge& o) const { return key < o.key || (key == o.key && forward < o.forward); }
  };
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * proper.size());
  for (const Eigen::Index f : proper)
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint32_t>(faces(f, k)), b = static_cast<std::uint32_t>(faces(f, (k + 1) % 3));
      half_edges.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b), a < b});
    }
  std::sort(half_edges.begin(), half_edges.end());
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t j = i, forward = 0;
    for (; j < half_edges.size() && half_edges[j].key == half_edges[i].key; ++j) forward += half_edges[j].forward;
    const std::size_t count = j - i;
    ++t.edges;
    if (count == 1) ++t.boundary_edges;
    else if (count > 2) ++t.nonmanifold_edges;
    else if (forward != 1) ++t.misoriented_edges;
    i = j;
  }

  // Components and referenced vertices.
  DisjointSets sets(vertex_count);
  std::vector<int> degree(static_cast<std::size_t>(vertex_count), 0);
  for (const Eigen::Index f : proper) {
    sets.unite(faces(f, 0), faces(f, 1));
    sets.unite(faces(f, 0), faces(f, 2));
    for (int k = 0; k < 3; ++k) ++degree[static_cast<std::size_t>(faces(f, k))];
  }
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    if (degree[static_cast<std::size_t>(v)] == 0) continue;
    ++t.referenced_vertices;
    if (sets.find(static_cast<int>(v)) == v) ++t.components;
  }

  // Fans: incident faces per vertex (CSR), then the link graph of each vertex in a reusable union-find whose
  // touched entries are reset afterwards, so the whole pass is O(F) rather than O(V * F).
  std::vector<std::size_t> start(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (Eigen::Index v = 0; v < vertex_count; ++v) start[static_cast<std::size_t>(v) + 1] = start[static_cast<std::size_t>(v)] + static_cast<std::size_t>(degree[static_cast<std::size_t>(v)]);
  std::vector<Eigen::Index> incident(start.back());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const Eigen::Index f : proper)
    for (int k = 0; k < 3; ++k) incident[fill[static_cast<std::size_t>(faces(f, k))]++] = f;
  DisjointSets link(vertex_count);
  std::vector<int> touched;
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    touched.clear();
    for (std::size_t i = start[static_cast<std::size_t>(v)]; i < start[static_cast<std::size_t>(v) + 1]; ++i) {
      const Eigen::Index f = incident[i];
      const int k = faces(f, 0) == v ? 0 : faces(f, 1) == v ? 1 : 2;
      const int x = faces(f, (k + 1) % 3), y = faces(f, (k + 2) % 3);
      link.unite(x, y);
      touched.push_back(x);
      touched.push_back(y);
    }
    if (touched.empty()) continue;
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    int fans = 0;
    for (const int x : touched) fans += link.find(x) == x;  // one root per fan
    if (fans > 1) ++t.nonmanifold_vertices;
    for (const int x : touched) link.parent[static_cast<std::size_t>(x)] = x;
  }
  return t;
}

}  // namespace wish::validation_detail
