// Real-segmentation-mesh defects (issue 11, docs/design/real-meshes.md): the robust operators and the map on constructed bad
// meshes. Every mesh here is closed, manifold and genus 0; each must get a BIJECTIVE map (0 flipped, 0 degenerate
// faces, degree 1) with its distortion reported as a verdict.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/spherical_map/coil_mesh.hpp"
#include "tests/spherical_map/map_checks.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

using testing::deformed_icosphere;

// testing::expect_bijective, with the mesh's name on a failure and a line of figures for the log.
void expect_bijective(const SphericalMapResult& r, const char* what) {
  SCOPED_TRACE(what);
  testing::expect_bijective(r);
  std::printf("[real] %-28s V=%5ld method %-8s attempts %zu K mean/p99 %.3f/%.3f verdict %s eps %.1e flips %ld "
              "neg.weights %ld repaired %ld stop %s %.2fs\n",
              what, static_cast<long>(r.sphere.rows()), to_string(r.method_used), r.attempts.size(),
              r.quality.conformal_mean, r.quality.conformal_p99, to_string(r.verdict), r.operator_stats.epsilon,
              r.operator_stats.flips, r.operator_stats.negative_weights_before, r.quality.repaired_vertices,
              to_string(r.attempts[static_cast<size_t>(r.chosen_attempt)].stop), r.seconds);
}

// Splits vertex v of a closed mesh along two of its edges (v, a) and (v, b) into v and a new twin at the SAME
// position: the faces of one side of the fan a..b move to the twin and two zero-area faces (v, a, twin) and
// (v, twin, b) close the slit — the defect of the confocal protrusion meshes (issue 11).
Mesh split_vertex(const Mesh& mesh, int v) {
  // Ordered fan of v: faces (v, x, y) CCW; walk from one face.
  std::vector<std::array<int, 3>> fan;
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.faces(f, k) == v) fan.push_back({static_cast<int>(f), mesh.faces(f, (k + 1) % 3), mesh.faces(f, (k + 2) % 3)});
  // Order the fan: next face starts where the previous ended (y of one == x of the next).
  std::vector<std::array<int, 3>> ordered{fan.front()};
  while (ordered.size() < fan.size())
    for (const auto& g : fan)
      if (g[1] == ordered.back()[2]) {
        ordered.push_back(g);
        break;
      }
  Mesh out = mesh;
  const int twin = static_cast<int>(mesh.vertex_count());
  out.vertices.conservativeResize(twin + 1, 3);
  out.vertices.row(twin) = mesh.vertices.row(v);
  const size_t half = ordered.size() / 2;
  for (size_t i = 0; i < half; ++i)
    for (int k = 0; k < 3; ++k)
      if (out.faces(ordered[i][0], k) == v) out.faces(ordered[i][0], k) = twin;
  const int a = ordered.front()[1], b = ordered[half - 1][2];
  const Eigen::Index nf = out.face_count();
  out.faces.conservativeResize(nf + 2, 3);
  out.faces.row(nf) = Eigen::RowVector3i(v, a, twin);
  out.faces.row(nf + 1) = Eigen::RowVector3i(v, twin, b);
  return out;
}

TEST(IntrinsicOperator, DelaunayFlipsRemoveEveryNegativeWeightAndKeepTheMetric) {
  // Voxel-like anisotropic ellipsoid: z stretched 3× and snapped to slices of 0.15 (needles and obtuse faces).
  const Mesh m = deformed_icosphere(4, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p.x(), 0.6 * p.y(), 0.15 * std::round(3.0 * p.z() / 0.15));
  });
  const geometry::IntrinsicOperator mollified =
      geometry::intrinsic_operator(m.vertices, m.faces, {geometry::LaplacianKind::Mollified});
  const geometry::IntrinsicOperator delaunay = geometry::intrinsic_operator(m.vertices, m.faces);
  EXPECT_GT(delaunay.stats.negative_weights_before, 100);  // the defect is there ...
  EXPECT_GT(delaunay.stats.flips, 0);
  EXPECT_EQ(delaunay.stats.negative_weights_after, 0);     // ... and gone
  EXPECT_FALSE(delaunay.stats.flip_cap_hit);
  for (const auto& e : delaunay.edges) EXPECT_GE(e.weight, 0.0);
  // Same metric: total area unchanged by flips, L·1 = 0, L symmetric.
  EXPECT_NEAR(delaunay.mass.sum(), mollified.mass.sum(), 1e-9 * mollified.mass.sum());
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(m.vertex_count());
  EXPECT_LT((delaunay.laplacian * ones).cwiseAbs().maxCoeff(), 1e-9 * delaunay.laplacian.diagonal().maxCoeff());
  EXPECT_LT((Eigen::SparseMatrix<double>(delaunay.laplacian.transpose()) - delaunay.laplacian).norm(), 1e-12);
  // Dirichlet energy of a linear function is the same for every triangulation of the same flat metric only on
  // flat patches; on the sphere-like surface it must stay close (within 2 %).
  const Eigen::VectorXd x = m.vertices.col(0);
  const double e0 = x.dot(mollified.laplacian * x), e1 = x.dot(delaunay.laplacian * x);
  EXPECT_NEAR(e1, e0, 0.02 * e0);
}

TEST(IntrinsicOperator, EqualsTheCotanLaplacianOnAnAlreadyDelaunayMesh) {
  // A subdivided icosahedron on the unit sphere: every edge is Delaunay (opposite angles sum to less than π), so the
  // intrinsic operator must do no flip and give exactly the extrinsic cotan Laplacian and the lumped mass of the
  // mesh's own triangles (no mollification on a clean mesh: ε = 0).
  const Mesh m = make_icosphere(3);
  const geometry::IntrinsicOperator op = geometry::intrinsic_operator(m.vertices, m.faces);
  EXPECT_EQ(op.stats.negative_weights_before, 0);
  EXPECT_EQ(op.stats.flips, 0);
  EXPECT_EQ(op.stats.epsilon, 0.0);
  const Eigen::SparseMatrix<double> cotan = geometry::cotan_laplacian(m.vertices, m.faces);
  const Eigen::SparseMatrix<double> difference = op.laplacian - cotan;
  EXPECT_LT(difference.norm(), 1e-12 * cotan.norm());
  EXPECT_LT((op.mass - geometry::lumped_mass(m.vertices, m.faces)).cwiseAbs().maxCoeff(), 1e-14);
  for (const auto& e : op.edges) EXPECT_GT(e.weight, 0.0);
}

TEST(IntrinsicOperator, MollificationMakesZeroAreaFacesValid) {
  const Mesh clean = make_icosphere(3);
  const Mesh split = split_vertex(clean, 0);
  const geometry::IntrinsicOperator op = geometry::intrinsic_operator(split.vertices, split.faces);
  EXPECT_EQ(op.stats.zero_area_faces, 2);
  EXPECT_GT(op.stats.epsilon, 0);
  EXPECT_GT(op.input_face_areas.minCoeff(), 0);
  EXPECT_TRUE(op.laplacian.coeffs().allFinite());
  EXPECT_GT(op.mass.minCoeff(), 0);
  // ε is the stated margin: δ·(mean edge) with the default δ, because the twins are at distance 0.
  EXPECT_NEAR(op.stats.relative_epsilon, geometry::IntrinsicOptions{}.mollify_delta, 1e-3 * op.stats.relative_epsilon);
}

TEST(RealMeshMap, DuplicateVertexWithZeroAreaFacesMapsLikeTheCleanMesh) {
  // The default path, as `wish describe`, `wish train` and /v1/classify run it: prepare_for_mapping with the default
  // repairs (welding on), then the default map of the prepared mesh.
  const Mesh clean = testing::make_ellipsoid(1.0, 0.7, 0.5, 3);
  const Mesh split = split_vertex(clean, 5);
  ASSERT_EQ(analyze_mesh(split).zero_area_faces, 2);  // the defect is there
  const PreparedMesh prepared = prepare_for_mapping(split);
  ASSERT_TRUE(prepared.mappable()) << prepared.issues.front().code << ": " << prepared.issues.front().message;
  const auto collapsed = std::find_if(prepared.repairs.begin(), prepared.repairs.end(),
                                      [](const RepairAction& r) { return r.code == "collapsed_zero_length_edges"; });
  ASSERT_NE(collapsed, prepared.repairs.end());
  EXPECT_EQ(collapsed->count, 1);
  // The twin is the last vertex and welds into vertex 5; the two zero-area faces were appended last: collapsing
  // their edge gives back the clean mesh exactly, so its map is the clean mesh's map.
  EXPECT_EQ(prepared.mesh.vertices, clean.vertices);
  EXPECT_EQ(prepared.mesh.faces, clean.faces);
  const SphericalMapResult a = compute_spherical_map(clean);
  const SphericalMapResult b = compute_spherical_map(prepared.mesh);
  expect_bijective(a, "ellipsoid clean");
  expect_bijective(b, "ellipsoid + twin vertex, repaired");
  EXPECT_EQ(b.operator_stats.zero_area_faces, 0);
  double worst = 0;
  for (Eigen::Index i = 0; i < clean.vertex_count(); ++i) worst = std::max(worst, (a.sphere.row(i) - b.sphere.row(i)).norm());
  EXPECT_LT(worst, 1e-12);
  EXPECT_NEAR(b.quality.conformal_mean, a.quality.conformal_mean, 1e-12 * a.quality.conformal_mean);
}

TEST(RealMeshMap, NeedleHeavyVoxelSampledSphereAndEllipsoidMapBijectively) {
  // Voxel-like sampling: z snapped to slices (anisotropic spacing 3× the in-plane one), the staircase needles of
  // marching cubes on anisotropic stacks.
  const Mesh sphere = deformed_icosphere(4, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p.x(), p.y(), 0.12 * std::round(p.z() / 0.12));
  });
  const Mesh ellipsoid = deformed_icosphere(4, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p.x(), 0.6 * p.y(), 0.3 * std::round(2.5 * p.z() / 0.3));
  });
  const Mesh sphere_clean = make_icosphere(4);
  const SphericalMapResult clean = compute_spherical_map(sphere_clean);
  const SphericalMapResult s = compute_spherical_map(sphere);
  const SphericalMapResult e = compute_spherical_map(ellipsoid);
  expect_bijective(s, "voxel-sampled sphere");
  expect_bijective(e, "voxel-sampled ellipsoid");
  EXPECT_GT(e.operator_stats.negative_weights_before, 0);
  // The voxel sphere is a sphere up to the staircase: its map stays close to conformal (clean K p99 ~1.0).
  EXPECT_LT(s.quality.conformal_mean, clean.quality.conformal_mean + 0.5);
}

TEST(RealMeshMap, DumbbellWithAThinNeckMapsBijectively) {
  // Neck radius 0.15 of the bulbs' 1: conformal maps compress the far bulb strongly.
  const Mesh dumbbell = deformed_icosphere(4, [](const Eigen::Vector3d& p) {
    const double s = 0.15 + 0.85 * std::pow(std::abs(p.x()), 0.7);
    return Eigen::Vector3d(2.5 * p.x(), s * p.y(), s * p.z());
  });
  expect_bijective(compute_spherical_map(dumbbell), "dumbbell (neck 0.15)");
}

TEST(RealMeshMap, CoilMapsBijectively) {
  const Mesh coil = testing::make_coil();  // 1.5 turns of a thin helical tube (coil_mesh.hpp)
  ASSERT_TRUE(prepare_for_mapping(coil).mappable());
  expect_bijective(compute_spherical_map(coil), "coil (1.5 turns)");
}

}  // namespace
}  // namespace wish
