#include "core/volume/taubin_smoothing.hpp"

#include <algorithm>
#include <vector>

namespace wish::volume {

void taubin_smooth(Mesh& mesh, int iterations, double lambda, double mu) {
  const Eigen::Index n = mesh.vertex_count();
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(n));
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = mesh.faces(f, k), j = mesh.faces(f, (k + 1) % 3);
      neighbours[i].push_back(j);
      neighbours[j].push_back(i);
    }
  for (auto& nb : neighbours) {
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
  Eigen::MatrixX3d delta(n, 3);
  auto step = [&](double factor) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto& nb = neighbours[static_cast<std::size_t>(i)];
      if (nb.empty()) {
        delta.row(i).setZero();
        continue;
      }
      Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
      for (int j : nb) mean += mesh.vertices.row(j);
      delta.row(i) = mean / static_cast<double>(nb.size()) - mesh.vertices.row(i);
    }
    mesh.vertices += factor * delta;
  };
  for (int it = 0; it < iterations; ++it) {
    step(lambda);
    step(mu);
  }
}

}  // namespace wish::volume
