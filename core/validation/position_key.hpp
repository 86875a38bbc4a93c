#pragma once
// Internal to core/validation: hash keys for exact comparisons. Two vertices are duplicates only when their
// coordinates are bit-for-bit equal after mapping -0.0 to 0.0 (no tolerance: any tolerance would be wrong for
// some unit of length).

#include <array>
#include <cstdint>
#include <cstring>

#include <Eigen/Core>

namespace wish::validation_detail {

using PositionKey = std::array<std::uint64_t, 3>;

inline PositionKey position_key(const Eigen::MatrixX3d& vertices, Eigen::Index v) {
  PositionKey key;
  for (int k = 0; k < 3; ++k) {
    const double x = vertices(v, k) + 0.0;  // -0.0 + 0.0 == +0.0
    std::memcpy(&key[static_cast<std::size_t>(k)], &x, sizeof x);
  }
  return key;
}

struct PositionHash {
  std::size_t operator()(const PositionKey& k) const noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (const std::uint64_t v : k) h = ((h ^ v) * 1099511628211ull) ^ (v >> 31);
    return static_cast<std::size_t>(h);
  }
};

struct TripleHash {
  std::size_t operator()(const std::array<int, 3>& k) const noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (const int v : k) h = (h ^ static_cast<std::uint32_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace wish::validation_detail
