#include "core/spherical_map/star_kernel_repair.hpp"

#include <algorithm>
#include <optional>
#include <utility>

#include "core/spherical_map/progressive_embedding.hpp"

namespace wish::spherical {
namespace {

// Faces around each vertex.
std::vector<std::vector<int>> faces_around(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count) {
  std::vector<std::vector<int>> around(static_cast<size_t>(vertex_count));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) around[static_cast<size_t>(faces(f, k))].push_back(static_cast<int>(f));
  return around;
}

long bad_faces_in(const Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces, const std::vector<int>& star,
                  double min_height) {
  long bad = 0;
  for (int f : star) bad += is_bad_sphere_face(sphere, faces, f, min_height);
  return bad;
}

// Places v in its star's kernel; true when it moved (its star then has no bad face).
bool place_vertex(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces, int v, const std::vector<int>& ring,
                  const std::vector<int>& star, double min_height, double margin) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> link;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (size_t j = 0; j < ring.size(); ++j) {
    link.emplace_back(sphere.row(ring[j]).transpose(), sphere.row(ring[(j + 1) % ring.size()]).transpose());
    centre += link.back().first;
  }
  if (!(centre.norm() > 0)) return false;
  const std::optional<Eigen::Vector3d> kernel = one_ring_kernel_centroid(centre.normalized(), link);
  if (!kernel) return false;
  const Eigen::Vector3d from = sphere.row(v).transpose();
  const auto at = [&](double t) { return ((1 - t) * from + t * *kernel).normalized(); };
  const auto star_good = [&](const Eigen::Vector3d& y) {
    sphere.row(v) = y.transpose();
    const bool good = bad_faces_in(sphere, faces, star, min_height) == 0;
    sphere.row(v) = from.transpose();
    return good;
  };
  // The great-circle path from `from` to the centroid is a line in the gnomonic chart, so once it enters the (convex)
  // kernel it stays inside: bisect the entry point, then go halfway on to the centroid.
  if (!kernel->allFinite() || !star_good(*kernel)) return false;
  double lo = 0, hi = 1;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (star_good(at(mid)) ? hi : lo) = mid;
  }
  const double t = hi + margin * (1 - hi);
  const Eigen::Vector3d y = star_good(at(t)) ? at(t) : *kernel;
  sphere.row(v) = y.transpose();
  return true;
}

// One pass of place_in_star_kernels with one margin.
StarKernelRepairResult kernel_pass(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces,
                                   const std::vector<std::vector<int>>& rings, const std::vector<std::vector<int>>& stars,
                                   double min_height, const StarKernelRepairOptions& options, double margin,
                                   const CpuBudget& budget) {
  StarKernelRepairResult result;
  result.margin = margin;
  const Eigen::Index nv = sphere.rows(), nf = faces.rows();
  std::vector<int> bad;
  const auto collect_bad = [&] {
    bad.clear();
    for (Eigen::Index f = 0; f < nf; ++f)
      if (is_bad_sphere_face(sphere, faces, f, min_height)) bad.push_back(static_cast<int>(f));
  };
  collect_bad();
  result.bad_faces_before = result.bad_faces_after = static_cast<long>(bad.size());
  if (bad.empty()) return result;
  std::vector<char> moved(static_cast<size_t>(nv), 0);
  // Rounds over the vertices of the bad faces. When a round removes none (every such vertex has an empty kernel: a
  // tangle of several vertices), the next one also moves their neighbours within `rings` rings whose stars are good
  // towards their kernels' centroids (they stay good: the kernel is where their star is), which opens up the tangled
  // vertices' kernels; the rings grow by one per stalled round up to options.max_rings.
  int rings_out = 0;
  for (int round = 0; round < options.max_rounds && !bad.empty(); ++round) {
    if ((result.budget_stopped = budget.expired())) break;
    std::vector<int> candidates;
    for (int f : bad)
      for (int k = 0; k < 3; ++k) candidates.push_back(faces(f, k));
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    std::vector<int> neighbours;
    if (rings_out > 0) {
      std::vector<char> in(static_cast<size_t>(nv), 0);
      for (int v : candidates) in[static_cast<size_t>(v)] = 1;
      std::vector<int> frontier = candidates;
      for (int r = 0; r < rings_out; ++r) {
        std::vector<int> next;
        for (int v : frontier)
          for (int w : rings[static_cast<size_t>(v)])
            if (!in[static_cast<size_t>(w)]) {
              in[static_cast<size_t>(w)] = 1;
              next.push_back(w);
            }
        neighbours.insert(neighbours.end(), next.begin(), next.end());
        frontier.swap(next);
      }
    }
    const long bad_before_round = static_cast<long>(bad.size());
    long moves = 0;
    for (int v : neighbours) {  // good stars, moved within their kernels
      const std::vector<int>& star = stars[static_cast<size_t>(v)];
      if (bad_faces_in(sphere, faces, star, min_height) != 0) continue;
      if (place_vertex(sphere, faces, v, rings[static_cast<size_t>(v)], star, min_height, 1.0)) {
        ++moves;
        moved[static_cast<size_t>(v)] = 1;
      }
    }
    for (int v : candidates) {
      const std::vector<int>& star = stars[static_cast<size_t>(v)];
      if (bad_faces_in(sphere, faces, star, min_height) == 0) continue;  // fixed by a neighbour's move
      if (!place_vertex(sphere, faces, v, rings[static_cast<size_t>(v)], star, min_height, margin)) continue;
      ++moves;
      moved[static_cast<size_t>(v)] = 1;
    }
    result.moves += moves;
    collect_bad();
    if (static_cast<long>(bad.size()) < bad_before_round) continue;
    if (rings_out >= options.max_rings) break;
    ++rings_out;
  }
  result.bad_faces_after = static_cast<long>(bad.size());
  result.moved_vertices = std::count(moved.begin(), moved.end(), 1);
  return result;
}

}  // namespace

StarKernelRepairResult place_in_star_kernels(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces,
                                             const std::vector<std::vector<int>>& rings,
                                             const MapVerificationThresholds& thresholds,
                                             const StarKernelRepairOptions& options, const CpuBudget& budget) {
  StarKernelRepairResult best;
  if (!sphere.allFinite()) return best;
  best.bad_faces_before = count_bad_sphere_faces(sphere, faces, thresholds.degenerate_height);
  best.bad_faces_after = best.bad_faces_before;
  if (best.bad_faces_before == 0 ||
      static_cast<double>(best.bad_faces_before) > options.max_bad_fraction * static_cast<double>(faces.rows()))
    return best;
  const std::vector<std::vector<int>> stars = faces_around(faces, sphere.rows());
  Eigen::MatrixX3d best_sphere = sphere;
  bool have = false;
  for (double margin : options.margins) {
    Eigen::MatrixX3d trial = sphere;
    const StarKernelRepairResult r = kernel_pass(trial, faces, rings, stars, thresholds.degenerate_height, options, margin, budget);
    if (!have || r.bad_faces_after < best.bad_faces_after) {
      best = r;
      best_sphere.swap(trial);
      have = true;
    }
    if (best.bad_faces_after == 0 || best.bad_faces_before == 0 || r.budget_stopped) break;
  }
  if (!have) return best;
  sphere.swap(best_sphere);
  return best;
}

}  // namespace wish::spherical

