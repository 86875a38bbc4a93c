// Voxel topology and handle removal (core/volume/voxel_topology.hpp, topology_repair.hpp).
// Analytic truths: a ball has b = (1, 0, 0), a solid torus (1, 1, 0), a shell (1, 0, 1), a ball drilled by k
// disjoint straight tunnels (1, k, 0). The simple-point table is checked against its definition: flipping a point
// keeps every Betti number of the set exactly when the table calls it simple. A repair must leave one component of
// genus 0 without cavities, change exactly the voxels it reports, and choose the cheaper of cutting and filling
// (a thin ring is cut, a thick ball with thin tunnels is filled).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/volume/marching_tetrahedra.hpp"
#include "core/volume/surface_topology.hpp"
#include "core/volume/topology_repair.hpp"
#include "core/volume/voxel_topology.hpp"

namespace wish::volume {
namespace {

BinaryVolume empty_grid(int n) {
  BinaryVolume v;
  v.dims = {n, n, n};
  v.labels.assign(static_cast<std::size_t>(n) * n * n, 0);
  return v;
}

template <class Inside>
BinaryVolume solid(int n, Inside inside) {
  BinaryVolume v = empty_grid(n);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) v.labels[v.index(x, y, z)] = inside(x - 0.5 * (n - 1), y - 0.5 * (n - 1), z - 0.5 * (n - 1));
  return v;
}

BinaryVolume solid_ball(int n, double r) {
  return solid(n, [r](double x, double y, double z) { return x * x + y * y + z * z <= r * r; });
}

// A ball of radius 11 with `k` (1..5) disjoint straight tunnels of width `w` voxels: four along x at y, z = ±5, one
// along y at x = z = 0... (the x tunnels pass at z = ±5, so they never meet the y tunnel).
BinaryVolume drilled_ball(int k, int w) {
  BinaryVolume v = solid_ball(29, 11);
  const int c = 14, lo = -(w - 1) / 2, hi = w / 2;
  const int at[4][2] = {{-5, -5}, {5, -5}, {-5, 5}, {5, 5}};
  for (int t = 0; t < k; ++t)
    for (int s = 0; s < 29; ++s)
      for (int a = lo; a <= hi; ++a)
        for (int b = lo; b <= hi; ++b) {
          if (t < 4) v.labels[v.index(s, c + at[t][0] + a, c + at[t][1] + b)] = 0;
          else v.labels[v.index(c + a, s, c + b)] = 0;
        }
  return v;
}

std::int64_t count(const BinaryVolume& v) {
  std::int64_t n = 0;
  for (auto l : v.labels) n += l;
  return n;
}

TEST(VoxelTopology, BettiNumbersOfAnalyticShapes) {
  const VoxelTopology b = voxel_topology(solid_ball(21, 8));
  EXPECT_EQ(b.components, 1);
  EXPECT_EQ(b.handles, 0);
  EXPECT_EQ(b.cavities, 0);
  const VoxelTopology torus = voxel_topology(solid(31, [](double x, double y, double z) {
    return std::pow(std::hypot(x, y) - 9, 2) + z * z <= 9;
  }));
  EXPECT_EQ(torus.components, 1);
  EXPECT_EQ(torus.handles, 1);
  EXPECT_EQ(torus.cavities, 0);
  const VoxelTopology shell = voxel_topology(solid(25, [](double x, double y, double z) {
    const double r = std::sqrt(x * x + y * y + z * z);
    return r <= 10 && r >= 6;
  }));
  EXPECT_EQ(shell.components, 1);
  EXPECT_EQ(shell.handles, 0);
  EXPECT_EQ(shell.cavities, 1);
  const VoxelTopology two = voxel_topology(solid(25, [](double x, double y, double z) {
    return (x - 6) * (x - 6) + y * y + z * z <= 16 || (x + 6) * (x + 6) + y * y + z * z <= 16;
  }));
  EXPECT_EQ(two.components, 2);
  EXPECT_EQ(two.handles, 0);
  for (int k = 1; k <= 5; ++k)
    for (int w = 1; w <= 3; ++w) EXPECT_EQ(voxel_topology(drilled_ball(k, w)).handles, k) << k << " tunnels of width " << w;
}

// The mask of a point's 14 neighbours in the volume (outside: not in the set).
std::uint32_t neighbour_mask(const BinaryVolume& v, int x, int y, int z) {
  std::uint32_t m = 0;
  const auto& o = link_offsets();
  for (std::size_t k = 0; k < 14; ++k) {
    const int a = x + o[k][0], b = y + o[k][1], c = z + o[k][2];
    if (a >= 0 && b >= 0 && c >= 0 && a < v.dims[0] && b < v.dims[1] && c < v.dims[2] && v.at(a, b, c)) m |= 1u << k;
  }
  return m;
}

TEST(VoxelTopology, EverySimplePointTableEntryMatchesItsDefinition) {
  // All 2^14 neighbourhoods: in a small grid holding only the point's neighbours, the point is simple exactly when
  // adding it changes no Betti number (its star is then a cone over the neighbours, so the neighbours must be
  // contractible, and the other neighbours then are too, by duality).
  BinaryVolume v = empty_grid(5);
  const auto& o = link_offsets();
  int simple = 0;
  for (std::uint32_t mask = 0; mask < (1u << 14); ++mask) {
    std::fill(v.labels.begin(), v.labels.end(), 0);
    for (std::size_t k = 0; k < 14; ++k)
      if (mask >> k & 1u) v.labels[v.index(2 + o[k][0], 2 + o[k][1], 2 + o[k][2])] = 1;
    const VoxelTopology before = voxel_topology(v);
    v.labels[v.index(2, 2, 2)] = 1;
    const VoxelTopology after = voxel_topology(v);
    const bool same = after.components == before.components && after.handles == before.handles &&
                      after.cavities == before.cavities;
    ASSERT_EQ(is_simple_point(mask), same) << "mask " << mask;
    simple += same;
  }
  EXPECT_GT(simple, 100);
  EXPECT_LT(simple, 1 << 13);
}

TEST(VoxelTopology, FlippingASimplePointKeepsTheTopologyOfARandomSet) {
  std::mt19937 rng(7);  // fixed seed: a failure reproduces
  int simple_seen = 0;
  for (int trial = 0; trial < 40; ++trial) {
    BinaryVolume v = empty_grid(9);
    std::bernoulli_distribution on(0.3 + 0.01 * trial);
    for (int z = 1; z < 8; ++z)
      for (int y = 1; y < 8; ++y)
        for (int x = 1; x < 8; ++x) v.labels[v.index(x, y, z)] = on(rng);
    const VoxelTopology before = voxel_topology(v);
    std::uniform_int_distribution<int> pick(2, 6);
    for (int flip = 0; flip < 30; ++flip) {
      const int x = pick(rng), y = pick(rng), z = pick(rng);
      if (!is_simple_point(neighbour_mask(v, x, y, z))) continue;
      ++simple_seen;
      v.labels[v.index(x, y, z)] ^= 1;
      const VoxelTopology after = voxel_topology(v);
      v.labels[v.index(x, y, z)] ^= 1;
      EXPECT_TRUE(after.components == before.components && after.handles == before.handles &&
                  after.cavities == before.cavities)
          << "trial " << trial << " point " << x << "," << y << "," << z;
    }
  }
  EXPECT_GT(simple_seen, 100);
}

// Every check a repair must pass: genus 0, one piece, no cavity, a closed genus-0 surface, and exactly the voxels it
// reports changed (removed ones from the object, added ones from the background).
void expect_valid_repair(const BinaryVolume& object, const TopologyRepair& r, int genus) {
  EXPECT_EQ(r.figures.genus_before, genus);
  const VoxelTopology t = voxel_topology(r.result);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.handles, 0);
  EXPECT_EQ(t.cavities, 0);
  EXPECT_TRUE(analyze_surface(marching_tetrahedra(r.result)).closed_genus0());
  std::int64_t removed = 0, added = 0;
  for (std::size_t i = 0; i < object.labels.size(); ++i) {
    removed += object.labels[i] && !r.result.labels[i];
    added += !object.labels[i] && r.result.labels[i];
  }
  EXPECT_EQ(removed, r.figures.removed);
  EXPECT_EQ(added, r.figures.added);
  EXPECT_EQ(r.figures.voxels_before, count(object));
  EXPECT_LE(r.figures.removed + r.figures.added, std::min(r.figures.cut_every_handle, r.figures.fill_every_tunnel));
}

TEST(TopologyRepair, ThinTunnelsThroughABallAreFilled) {
  for (int k = 1; k <= 5; ++k)
    for (int w = 1; w <= 3; ++w) {
      SCOPED_TRACE(std::to_string(k) + " tunnels of width " + std::to_string(w));
      const BinaryVolume v = drilled_ball(k, w);
      const TopologyRepair r = remove_handles(v);
      expect_valid_repair(v, r, k);
      EXPECT_EQ(r.figures.removed, 0);  // plugging a tunnel costs w^2 voxels, cutting the ball far more
      EXPECT_EQ(r.figures.fills, k);
      EXPECT_STREQ(r.figures.method(), "fill");
      EXPECT_EQ(r.figures.added, k * w * w);  // one plug across each tunnel, not the tunnel
      EXPECT_LT(r.figures.volume_change(), 0.01);
    }
}

TEST(TopologyRepair, AThinRingIsCutWhereItIsThinnest) {
  // A ring of tube radius 2 around a hole of radius 10: cutting the tube costs a cross-section (about 13 voxels),
  // filling the hole a disc of hundreds.
  const BinaryVolume ring = solid(31, [](double x, double y, double z) {
    const double thick = 2 + (x > 0 ? 1.5 : 0);  // thinner on one side: the cut goes there
    return std::pow(std::hypot(x, y) - 10, 2) + z * z <= thick * thick;
  });
  const TopologyRepair r = remove_handles(ring);
  expect_valid_repair(ring, r, 1);
  EXPECT_STREQ(r.figures.method(), "cut");
  EXPECT_EQ(r.figures.cuts, 1);
  EXPECT_LT(r.figures.removed, 30);
  EXPECT_GT(r.figures.fill_every_tunnel, 5 * r.figures.removed);
  for (std::size_t i = 0; i < ring.labels.size(); ++i) {
    if (ring.labels[i] && !r.result.labels[i]) {
      EXPECT_LT(i % 31, 15u) << "a cut on the thick side";
    }
  }
  EXPECT_NE(r.figures.describe().find("cut 1 handle (-"), std::string::npos) << r.figures.describe();
}

TEST(TopologyRepair, MixedHandlesAreEachCutOrFilledWhicheverIsSmaller) {
  // A ball drilled by a thin tunnel (fill: 1 voxel) with a thin ring attached beside it (cut: a few voxels).
  BinaryVolume v = drilled_ball(1, 1);
  BinaryVolume ring = solid(29, [](double x, double y, double z) {
    return std::pow(std::hypot(x - 6, z) - 5, 2) + (y - 10) * (y - 10) <= 1.5;
  });
  for (std::size_t i = 0; i < v.labels.size(); ++i) v.labels[i] |= ring.labels[i];
  const VoxelTopology t = voxel_topology(v);
  ASSERT_EQ(t.components, 1);
  const TopologyRepair r = remove_handles(v);
  expect_valid_repair(v, r, static_cast<int>(t.handles));
  EXPECT_GT(r.figures.removed, 0);
  EXPECT_GT(r.figures.added, 0);
  EXPECT_STREQ(r.figures.method(), "cut_and_fill");
}

TEST(TopologyRepair, AGenusZeroObjectIsLeftAlone) {
  const BinaryVolume v = solid_ball(15, 5);
  const TopologyRepair r = remove_handles(v);
  EXPECT_EQ(r.figures.genus_before, 0);
  EXPECT_EQ(r.result.labels, v.labels);
  EXPECT_STREQ(r.figures.method(), "none");
}

}  // namespace
}  // namespace wish::volume
