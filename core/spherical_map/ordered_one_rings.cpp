#include "core/spherical_map/ordered_one_rings.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace wish::spherical {

std::optional<std::vector<std::vector<int>>> ordered_one_rings(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count) {
  // Per vertex the pairs (b, c) of its faces (v, b, c): "after b comes c".
  std::vector<std::vector<std::pair<int, int>>> next(static_cast<size_t>(vertex_count));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      next[static_cast<size_t>(faces(f, k))].emplace_back(faces(f, (k + 1) % 3), faces(f, (k + 2) % 3));
  std::vector<std::vector<int>> rings(static_cast<size_t>(vertex_count));
  for (size_t v = 0; v < rings.size(); ++v) {
    std::vector<std::pair<int, int>>& pairs = next[v];
    if (pairs.size() < 3) return std::nullopt;
    std::sort(pairs.begin(), pairs.end());
    std::vector<int>& ring = rings[v];
    int at = pairs.front().first;
    for (size_t step = 0; step < pairs.size(); ++step) {
      ring.push_back(at);
      const auto it = std::lower_bound(pairs.begin(), pairs.end(), std::make_pair(at, std::numeric_limits<int>::min()));
      if (it == pairs.end() || it->first != at || (it + 1 != pairs.end() && (it + 1)->first == at)) return std::nullopt;
      at = it->second;
    }
    if (at != ring.front()) return std::nullopt;
  }
  return rings;
}

}  // namespace wish::spherical
