#include "core/spherical_map/untangle.hpp"

#include <algorithm>
#include <vector>

#include <Eigen/Geometry>

#include "core/spherical_map/map_verification.hpp"

namespace wish::spherical {
UntangleResult untangle_sphere_map(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces,
                                   const MapVerificationThresholds& thresholds, const UntangleOptions& options,
                                   const CpuBudget& budget) {
  UntangleResult result;
  const Eigen::Index nv = sphere.rows(), nf = faces.rows();
  if (!sphere.allFinite()) return result;
  auto find_bad = [&] {
    std::vector<Eigen::Index> bad;
    for (Eigen::Index f = 0; f < nf; ++f)
      if (is_bad_sphere_face(sphere, faces, f, thresholds.degenerate_height)) bad.push_back(f);
    return bad;
  };
  std::vector<Eigen::Index> bad = find_bad();
  result.bad_faces_before = result.bad_faces_after = static_cast<long>(bad.size());
  if (bad.empty()) return result;

  // Vertex adjacency.
  std::vector<std::vector<int>> neighbours(static_cast<size_t>(nv));
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) neighbours[static_cast<size_t>(faces(f, k))].push_back(faces(f, (k + 1) % 3));
  for (auto& n : neighbours) {  // closed manifold: each neighbour appears once as "next" — keep as is, but dedupe
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  std::vector<char> in_patch(static_cast<size_t>(nv), 0);
  std::vector<int> patch;
  auto add = [&](int v) {
    if (!in_patch[static_cast<size_t>(v)]) {
      in_patch[static_cast<size_t>(v)] = 1;
      patch.push_back(v);
    }
  };
  auto grow = [&] {
    const std::vector<int> current = patch;
    for (int v : current)
      for (int w : neighbours[static_cast<size_t>(v)]) add(w);
  };
  const Eigen::MatrixX3d original = sphere;
  const size_t limit = static_cast<size_t>(
      std::max(options.max_fraction * static_cast<double>(nv), static_cast<double>(options.min_patch)));
  for (Eigen::Index f : bad)
    for (int k = 0; k < 3; ++k) add(faces(f, k));
  for (int r = 0; r < options.rings; ++r) grow();
  for (int round = 0; round < options.max_rounds && patch.size() <= limit; ++round) {
    // Gauss–Seidel converges in O(patch diameter²) sweeps; a fixed minimum plus the patch size covers small patches.
    const int sweeps = std::min(options.max_sweeps, std::max(options.sweeps, static_cast<int>(patch.size())));
    for (int sweep = 0; sweep < sweeps; ++sweep) {
      if ((result.budget_stopped = budget.expired())) break;
      for (int v : patch) {
        Eigen::Vector3d s = Eigen::Vector3d::Zero();
        for (int w : neighbours[static_cast<size_t>(v)]) s += sphere.row(w).transpose();
        const double norm = s.norm();
        if (norm > 0) sphere.row(v) = (s / norm).transpose();
      }
    }
    if (result.budget_stopped) break;
    bad = find_bad();
    if (bad.empty()) break;
    for (Eigen::Index f : bad)
      for (int k = 0; k < 3; ++k) add(faces(f, k));
    grow();
  }
  result.bad_faces_after = static_cast<long>(bad.size());
  if (result.budget_stopped || !bad.empty()) {  // no success: leave the map as it was (the caller reports the original failure)
    sphere = original;
    result.bad_faces_after = result.bad_faces_before;
    return result;
  }
  for (Eigen::Index i = 0; i < nv; ++i)
    if (sphere.row(i) != original.row(i)) ++result.moved_vertices;
  return result;
}

}  // namespace wish::spherical
