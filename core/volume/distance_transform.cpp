#include "core/volume/distance_transform.hpp"

#include <algorithm>
#include <limits>

namespace wish::volume {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One axis: f (n values, stride apart in `d`) becomes min_q f(q) + (w (p − q))^2. `v`, `z`, `g` are scratch.
void envelope_1d(double* d, std::size_t stride, int n, double w, std::vector<int>& v, std::vector<double>& z,
                 std::vector<double>& g) {
  for (int i = 0; i < n; ++i) g[static_cast<std::size_t>(i)] = d[static_cast<std::size_t>(i) * stride];
  const double w2 = w * w;
  int k = -1;
  for (int q = 0; q < n; ++q) {
    const double fq = g[static_cast<std::size_t>(q)];
    if (fq == kInf) continue;
    // Intersection of the parabola from q with the last on the envelope, in grid units.
    while (k >= 0) {
      const int p = v[static_cast<std::size_t>(k)];
      const double s = ((fq + w2 * q * q) - (g[static_cast<std::size_t>(p)] + w2 * p * p)) / (2 * w2 * (q - p));
      if (s > z[static_cast<std::size_t>(k)]) break;
      --k;
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = k == 0 ? -kInf
                                            : ((fq + w2 * q * q) - (g[static_cast<std::size_t>(v[k - 1])] +
                                                                    w2 * v[k - 1] * v[k - 1])) /
                                                  (2 * w2 * (q - v[k - 1]));
    z[static_cast<std::size_t>(k) + 1] = kInf;
  }
  if (k < 0) return;  // no finite value on this line: it stays infinite
  int j = 0;
  for (int p = 0; p < n; ++p) {
    while (z[static_cast<std::size_t>(j) + 1] < p) ++j;
    const int q = v[static_cast<std::size_t>(j)];
    d[static_cast<std::size_t>(p) * stride] = g[static_cast<std::size_t>(q)] + w2 * (p - q) * (p - q);
  }
}

}  // namespace

std::vector<double> squared_distance_to(const BinaryVolume& volume, std::uint8_t target) {
  std::vector<double> d(volume.labels.size());
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = volume.labels[i] == target ? 0.0 : kInf;
  const int n[3] = {volume.dims[0], volume.dims[1], volume.dims[2]};
  const std::size_t stride[3] = {1, static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[0]) * n[1]};
  const int longest = std::max(n[0], std::max(n[1], n[2]));
  std::vector<int> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1), g(static_cast<std::size_t>(longest));
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // the two other axes
    for (int j = 0; j < n[b]; ++j)
      for (int i = 0; i < n[a]; ++i)
        envelope_1d(d.data() + stride[a] * i + stride[b] * j, stride[axis], n[axis], volume.spacing(axis), v, z, g);
  }
  return d;
}

}  // namespace wish::volume
