// The progressive embedding (progressive_embedding.hpp): the chain's last resort must give a bijective sphere map
// (0 flipped, 0 degenerate faces, degree 1) on shapes whose conformal maps underflow — a coil, dumbbells with thin
// necks — and on irregular re-triangulations, with the area of thin parts kept representable; and it must end the
// default chain where every other method fails.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <utility>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/io/mesh_io.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/progressive_embedding.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/spherical_map/coil_mesh.hpp"
#include "tests/spherical_map/map_checks.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

// Sphere area share over input area share, per face (face_distortion's area_ratio).
Eigen::VectorXd area_ratios(const Mesh& m, const Eigen::MatrixX3d& u) {
  return spherical::face_distortion(m.vertices, m.faces, u).area_ratio;
}

// The method alone, then checked like the chain checks every map.
MapQuality progressive_quality(const Mesh& m, Eigen::MatrixX3d* sphere = nullptr) {
  const spherical::MapContext context(m);
  const spherical::FlowResult r = spherical::progressive_map(context, {});
  EXPECT_EQ(r.status, MapStatus::Ok) << r.message;
  EXPECT_TRUE(r.on_sphere);
  if (sphere) *sphere = r.vertices;
  return spherical::measure_map(m.vertices, m.faces, r.vertices, {});
}

using testing::expect_bijective;

// Two unit balls joined by a neck of radius `neck` (an icosphere of level 4 stretched along x).
Mesh make_dumbbell(double neck) {
  Mesh m = make_icosphere(4);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const Eigen::Vector3d p = m.vertices.row(i).transpose();
    const double s = std::sin(std::numbers::pi * p.x());
    const double scale = neck + (1.0 - neck) * s * s;
    m.vertices.row(i) = Eigen::RowVector3d(2.5 * p.x(), scale * p.y(), scale * p.z());
  }
  return m;
}

// A closed tube along a helix (radius 1, pitch 0.8) with nearly equilateral faces, as marching cubes makes a coil
// (unlike make_coil's bent ellipsoid, whose faces stretch along the tube): `around` vertices per ring, rings spaced
// by the edge length around and staggered by half a step, a fan cap at each end.
Mesh tube_coil(double turns, double wire, int around) {
  const double pitch = 0.8 / (2 * std::numbers::pi), length = 2 * std::numbers::pi * turns * std::sqrt(1 + pitch * pitch);
  const int rings = static_cast<int>(std::ceil(length / (2 * std::numbers::pi * wire / around)));
  Mesh m;
  m.vertices.resize(rings * around + 2, 3);
  const auto centre = [&](double t) { return Eigen::Vector3d(std::cos(t), std::sin(t), pitch * t); };
  for (int i = 0; i < rings; ++i) {
    const double t = 2 * std::numbers::pi * turns * i / (rings - 1);
    const Eigen::Vector3d tangent = Eigen::Vector3d(-std::sin(t), std::cos(t), pitch).normalized();
    const Eigen::Vector3d normal(-std::cos(t), -std::sin(t), 0), binormal = tangent.cross(normal);
    for (int j = 0; j < around; ++j) {
      const double a = 2 * std::numbers::pi * (j + 0.5 * (i % 2)) / around;
      m.vertices.row(i * around + j) = (centre(t) + wire * (std::cos(a) * normal + std::sin(a) * binormal)).transpose();
    }
  }
  const int first = rings * around, last = first + 1;
  m.vertices.row(first) = (centre(0) - 0.5 * wire * Eigen::Vector3d(0, 1, pitch).normalized()).transpose();
  const double t_end = 2 * std::numbers::pi * turns;
  m.vertices.row(last) = (centre(t_end) + 0.5 * wire * Eigen::Vector3d(-std::sin(t_end), std::cos(t_end), pitch).normalized()).transpose();
  std::vector<Eigen::Vector3i> faces;
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < around; ++j) {
      const int a = i * around + j, b = i * around + (j + 1) % around, c = (i + 1) * around + j,
                d = (i + 1) * around + (j + 1) % around;
      if (i % 2 == 0) {
        faces.emplace_back(a, b, c);
        faces.emplace_back(b, d, c);
      } else {
        faces.emplace_back(a, d, c);
        faces.emplace_back(a, b, d);
      }
    }
  for (int j = 0; j < around; ++j) {
    faces.emplace_back(first, (j + 1) % around, j);
    faces.emplace_back(last, (rings - 1) * around + j, (rings - 1) * around + (j + 1) % around);
  }
  m.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) m.faces.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  return m;
}
// Random edge flips of an icosphere (kept valid: the new edge must not exist, no vertex below degree 3), so the
// triangulation has irregular valences, and a small random jitter of the positions.
Mesh random_retriangulation(unsigned seed, int flips) {
  Mesh m = make_icosphere(3);
  std::mt19937 rng(seed);
  const auto edge_faces = [&](int a, int b, int& f0, int& f1) {
    f0 = f1 = -1;
    for (Eigen::Index f = 0; f < m.face_count(); ++f)
      for (int k = 0; k < 3; ++k)
        if (m.faces(f, k) == a && m.faces(f, (k + 1) % 3) == b) f0 = static_cast<int>(f);
        else if (m.faces(f, k) == b && m.faces(f, (k + 1) % 3) == a) f1 = static_cast<int>(f);
  };
  std::vector<int> degree(static_cast<size_t>(m.vertex_count()), 0);
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.faces(f, k), b = m.faces(f, (k + 1) % 3);
      if (a < b) edges.insert({a, b});
      ++degree[static_cast<size_t>(a)];
    }
  std::uniform_int_distribution<Eigen::Index> pick_face(0, m.face_count() - 1);
  for (int done = 0, tries = 0; done < flips && tries < 100 * flips; ++tries) {
    const Eigen::Index f = pick_face(rng);
    const int k = static_cast<int>(rng() % 3);
    const int a = m.faces(f, k), b = m.faces(f, (k + 1) % 3);
    int f0, f1;
    edge_faces(a, b, f0, f1);
    if (f0 < 0 || f1 < 0) continue;
    int c = -1, d = -1;  // c opposite in f0 (a, b, c), d opposite in f1 (b, a, d)
    for (int j = 0; j < 3; ++j) {
      if (m.faces(f0, j) != a && m.faces(f0, j) != b) c = m.faces(f0, j);
      if (m.faces(f1, j) != a && m.faces(f1, j) != b) d = m.faces(f1, j);
    }
    if (edges.count({std::min(c, d), std::max(c, d)}) || degree[static_cast<size_t>(a)] <= 4 ||
        degree[static_cast<size_t>(b)] <= 4)
      continue;
    m.faces.row(f0) = Eigen::RowVector3i(a, d, c);
    m.faces.row(f1) = Eigen::RowVector3i(b, c, d);
    edges.erase({std::min(a, b), std::max(a, b)});
    edges.insert({std::min(c, d), std::max(c, d)});
    --degree[static_cast<size_t>(a)];
    --degree[static_cast<size_t>(b)];
    ++degree[static_cast<size_t>(c)];
    ++degree[static_cast<size_t>(d)];
    ++done;
  }
  std::normal_distribution<double> noise(0.0, 0.01);
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i)
    for (int j = 0; j < 3; ++j) m.vertices(i, j) += noise(rng);
  return m;
}

// The placement step: the kernel of a hexagram-shaped one-ring (outer corners at radius 0.3, inner at 0.3/√3) in
// the gnomonic chart about the north pole is its inner hexagon, so its centroid is the hexagram's centre — for any
// shift of the ring in the chart (great circles are lines there). A ring with spikes this sharp has a kernel much
// smaller than the ring (a point near an outer corner sees the neighbouring spikes' edges from the wrong side).
TEST(ProgressiveEmbedding, KernelCentroidOfAHexagramIsItsCentre) {
  for (const Eigen::Vector2d& shift : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.05, -0.03), Eigen::Vector2d(-0.06, 0.02)}) {
    SCOPED_TRACE(shift.transpose());
    std::vector<Eigen::Vector3d> ring;
    for (int i = 0; i < 12; ++i) {
      const double r = i % 2 == 0 ? 0.3 : 0.3 / std::sqrt(3.0), angle = i * std::numbers::pi / 6;
      ring.push_back(Eigen::Vector3d(shift.x() + r * std::cos(angle), shift.y() + r * std::sin(angle), 1).normalized());
    }
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> link;
    for (size_t i = 0; i < ring.size(); ++i) link.emplace_back(ring[i], ring[(i + 1) % ring.size()]);
    const std::optional<Eigen::Vector3d> y = spherical::one_ring_kernel_centroid(Eigen::Vector3d::UnitZ(), link);
    ASSERT_TRUE(y.has_value());
    const Eigen::Vector3d expected = Eigen::Vector3d(shift.x(), shift.y(), 1).normalized();
    EXPECT_LT((*y - expected).norm(), 1e-12);
    for (const auto& [a, b] : link) EXPECT_GT(y->dot(a.cross(b)), 0);  // sees every link edge from the left
    // An outer corner pulled in (0.3 → 0.16) keeps a star-shaped ring; the kernel shrinks to that side, and the
    // centroid still sees every edge.
    link.front().first = link.back().second = Eigen::Vector3d(shift.x() + 0.16, shift.y(), 1).normalized();
    const std::optional<Eigen::Vector3d> z = spherical::one_ring_kernel_centroid(Eigen::Vector3d::UnitZ(), link);
    ASSERT_TRUE(z.has_value());
    for (const auto& [a, b] : link) EXPECT_GT(z->dot(a.cross(b)), 0);
  }
  // An edge and its reverse (no point sees both from the left): no kernel.
  const Eigen::Vector3d a = Eigen::Vector3d(0.2, 0, 1).normalized(), b = Eigen::Vector3d(0, 0.2, 1).normalized();
  EXPECT_FALSE(spherical::one_ring_kernel_centroid(Eigen::Vector3d::UnitZ(), {{a, b}, {b, a}}).has_value());
}

TEST(ProgressiveEmbedding, CoilMapsBijectivelyWithItsMiddleRepresentable) {
  const Mesh coil = testing::make_coil();
  Eigen::MatrixX3d u;
  const MapQuality q = progressive_quality(coil, &u);
  expect_bijective(q);
  // A conformal map squeezes a tube exponentially in length/radius (the coil is ~40 radii long); the progressive
  // map spreads vertices evenly, so no part of the coil loses more than a bounded factor of its area share.
  const Eigen::VectorXd ratio = area_ratios(coil, u);
  EXPECT_GT(ratio.minCoeff(), 1e-3);
  EXPECT_LT(ratio.maxCoeff(), 1e3);
  EXPECT_GT(q.min_face_area, 1e-8);
  std::printf("[progressive] coil: K p99 %.2f, area ratio %.3g..%.3g, area distortion %.3f\n", q.conformal_p99,
              ratio.minCoeff(), ratio.maxCoeff(), q.area_distortion);
}

TEST(ProgressiveEmbedding, ThinDumbbellsMapBijectively) {
  for (const double neck : {0.2, 0.05}) {
    SCOPED_TRACE(neck);
    const Mesh m = make_dumbbell(neck);
    Eigen::MatrixX3d u;
    const MapQuality q = progressive_quality(m, &u);
    expect_bijective(q);
    const Eigen::VectorXd ratio = area_ratios(m, u);
    EXPECT_GT(ratio.minCoeff(), 1e-3);
    std::printf("[progressive] dumbbell 1:%.0f: K p99 %.2f, area ratio %.3g..%.3g\n", 1 / neck, q.conformal_p99,
                ratio.minCoeff(), ratio.maxCoeff());
  }
}

TEST(ProgressiveEmbedding, RandomRetriangulationsMapBijectively) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(seed);
    const Mesh m = random_retriangulation(seed, 300);
    expect_bijective(progressive_quality(m));
  }
}

TEST(ProgressiveEmbedding, IsARecipeMethodOfItsOwn) {
  EXPECT_EQ(map_method_from_name("progressive"), MapMethod::Progressive);
  SphericalMapOptions o;
  o.method = MapMethod::Progressive;
  o.fallback = false;
  const SphericalMapResult r = compute_spherical_map(testing::make_coil(), o);
  ASSERT_EQ(r.attempts.size(), 1u);
  EXPECT_EQ(r.method_used, MapMethod::Progressive);
  EXPECT_TRUE(r.ok()) << r.attempts.front().message;
  EXPECT_EQ(r.quality.flipped_faces, 0);
  EXPECT_EQ(r.quality.degree, 1);
}

TEST(ProgressiveEmbedding, EndsEveryChainWithFallback) {
  for (const MapMethod method : {MapMethod::Willmore, MapMethod::Cmcf, MapMethod::Linear}) {
    SphericalMapOptions o;
    o.method = method;
    const std::vector<MapAttemptPlan> plans = plan_attempts(o);
    ASSERT_GT(plans.size(), 1u);
    EXPECT_EQ(plans.back().method, MapMethod::Progressive) << to_string(method);
    for (size_t k = 0; k + 1 < plans.size(); ++k) EXPECT_NE(plans[k].method, MapMethod::Progressive) << to_string(method);
    o.fallback = false;
    EXPECT_EQ(plan_attempts(o).size(), 1u);  // no fallback: the requested method alone
  }
}

TEST(ProgressiveEmbedding, DoesNotRunWhenAnEarlierMethodMaps) {
  // A mesh the first attempt maps keeps that map: the last resort is not tried (the maps of meshes that mapped
  // before it joined the chain do not change).
  const SphericalMapResult r = compute_spherical_map(make_icosphere(3));
  ASSERT_TRUE(r.ok());
  for (const MapAttempt& a : r.attempts) EXPECT_NE(a.method, MapMethod::Progressive);
}

// Shared real meshes on which every other attempt of the default chain before the needle retry leaves flips
// (Willmore stalls with 20–1,087 flipped faces, cMCF and both linear maps fail too): the default chain, as `wish map`
// runs it, ends on the progressive embedding — or on the needle retry's flow (spine_7: Willmore) — with a verified
// map whose area distortion stays bounded (the uniform spreading alone left ~1e6 on the nmv spines; the needle
// retry's small-step cMCF 2.6e9 on nmv_spine_3, which the chain therefore does not take: kNeedleMaxAreaDistortion).
// nmv_spine_25 (9,306 vertices) found no kernel point before the kernel was computed exactly (half-plane clipping in
// the gnomonic chart).
TEST(ProgressiveEmbedding, EndsTheDefaultChainOnSharedMeshesThatFailEveryOtherMethod) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const std::filesystem::path hard = *testing::shared_data_dir() / "hard";
  for (const char* name : {"hvcl_spines/spine_7.off", "nmv_spines/nmv_spine_3.obj", "nmv_spines/nmv_spine_4.obj",
                           "nmv_spines/nmv_spine_25.obj"}) {
    SCOPED_TRACE(name);
    if (!std::filesystem::exists(hard / name)) continue;
    const PreparedMesh prepared = prepare_for_mapping(read_mesh_file(hard / name).mesh);
    ASSERT_TRUE(prepared.mappable());
    const SphericalMapResult r = compute_spherical_map(prepared.mesh);
    EXPECT_TRUE(r.ok()) << to_string(r.failed_check) << ": " << r.attempts.back().message;
    const MapAttempt& chosen = r.attempts.at(static_cast<size_t>(r.chosen_attempt));
    if (!chosen.needle) {
      EXPECT_EQ(r.method_used, MapMethod::Progressive);
    }
    EXPECT_EQ(r.quality.flipped_faces, 0);
    EXPECT_EQ(r.quality.degenerate_faces, 0);
    EXPECT_EQ(r.quality.degree, 1);
    EXPECT_LT(r.quality.area_distortion, 100);
    std::printf("[progressive] %-28s ended on %s after %zu attempts, K p99 %.1f, area distortion %.2f\n", name,
                to_string(r.method_used), r.attempts.size(), r.quality.conformal_p99, r.quality.area_distortion);
  }
}

// How many neighbourhood spreads an embedding's placements needed, from the attempt's message ("NAME <stretch> (N
// spread)" or "NAME given up (N spread)"); -1 when the message does not name it.
int spreads_of(const std::string& message, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(message, m, std::regex(name + " [^(]+ \\(([0-9]+) spread\\)"))) return -1;
  return std::stoi(m[1].str());
}

// The progressive map of `mesh` with the default uniform spread limit and without any limit.
struct WithAndWithoutSpreadLimit {
  spherical::FlowResult limited, full;
};
WithAndWithoutSpreadLimit map_with_and_without_spread_limit(const Mesh& mesh) {
  const spherical::MapContext context(mesh);
  ProgressiveOptions no_limit;
  no_limit.uniform_max_spreads = 0;
  return {spherical::progressive_map(context, {}), spherical::progressive_map(context, no_limit)};
}

// The uniform spreading is given up at ProgressiveOptions::uniform_max_spreads: on a thin tube with even faces it
// crowds the tube (a kernel thinner than the height margin, again and again) and loses to the stretch spreading,
// so the map with the limit is the map without it, bit for bit — the limit only saves the spreads (on the fine
// 6-turn coil: 2,446 of them, ~2 CPU s).
TEST(ProgressiveEmbedding, GivesUpACrowdedUniformSpreadingWithTheSameMap) {
  const Mesh tube = tube_coil(2, 0.1, 6);
  const auto [limited, full] = map_with_and_without_spread_limit(tube);
  ASSERT_EQ(limited.status, MapStatus::Ok) << limited.message;
  ASSERT_EQ(full.status, MapStatus::Ok) << full.message;
  EXPECT_NE(limited.message.find("uniform given up"), std::string::npos) << limited.message;
  EXPECT_EQ(spreads_of(limited.message, "uniform"), ProgressiveOptions{}.uniform_max_spreads) << limited.message;
  EXPECT_GT(spreads_of(full.message, "uniform"), ProgressiveOptions{}.uniform_max_spreads) << full.message;
  EXPECT_EQ(full.message.find("given up"), std::string::npos) << full.message;
  EXPECT_TRUE(limited.vertices == full.vertices);
  expect_bijective(spherical::measure_map(tube.vertices, tube.faces, limited.vertices, {}));
}

// A uniform spreading that needs no spread is untouched by the limit: on make_coil's bent ellipsoid it is the
// embedding kept, with or without the limit, and the maps are the same.
TEST(ProgressiveEmbedding, KeepsAUniformSpreadingThatNeedsNoSpread) {
  const auto [limited, full] = map_with_and_without_spread_limit(testing::make_coil(3, 0.1));
  ASSERT_EQ(limited.status, MapStatus::Ok) << limited.message;
  EXPECT_NE(limited.message.find("uniform spreading"), std::string::npos) << limited.message;
  EXPECT_EQ(spreads_of(limited.message, "uniform"), 0) << limited.message;
  EXPECT_TRUE(limited.vertices == full.vertices);
}

}  // namespace
}  // namespace wish
