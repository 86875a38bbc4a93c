// Operator identities and curvature facts of docs/design/spherical-map.md §1 / §9.
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

#include "core/common/errors.hpp"
#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/mean_curvature.hpp"
#include "core/geometry/roundness.hpp"
#include "core/geometry/vertex_normals.hpp"
#include "core/mesh/icosphere.hpp"
#include "tests/testing/test_data.hpp"

namespace wish::geometry {
namespace {

TEST(IntrinsicOperator, LaplacianIsTheEdgeListAssembledAndTheEdgesAreSortedAndDistinct) {
  // A snapped, stretched ellipsoid (needles and obtuse faces, so the Delaunay operator flips): whatever the
  // assembly, L must be −w_ij off the diagonal for each listed edge, Σ_j w_ij on it, nothing else, with sorted rows.
  Mesh mesh = testing::make_ellipsoid(1.0, 0.6, 2.0, 3);
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    mesh.vertices(i, 2) = 0.15 * std::round(mesh.vertices(i, 2) / 0.15);
  for (const LaplacianKind kind : {LaplacianKind::Mollified, LaplacianKind::IntrinsicDelaunay}) {
    const IntrinsicOperator op = intrinsic_operator(mesh.vertices, mesh.faces, {kind});
    if (kind == LaplacianKind::IntrinsicDelaunay) {
      EXPECT_GT(op.stats.flips, 0);
    }
    const Eigen::Index n = mesh.vertex_count();
    std::vector<Eigen::Triplet<double>> t;
    Eigen::VectorXd diag = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < op.edges.size(); ++k) {
      const IntrinsicEdgeWeight& e = op.edges[k];
      ASSERT_LT(e.i, e.j);
      if (k > 0) {
        const IntrinsicEdgeWeight& p = op.edges[k - 1];
        EXPECT_TRUE(p.i < e.i || (p.i == e.i && p.j < e.j)) << "edges not sorted and distinct at " << k;
      }
      t.emplace_back(e.i, e.j, -e.weight);
      t.emplace_back(e.j, e.i, -e.weight);
      diag[e.i] += e.weight;
      diag[e.j] += e.weight;
    }
    for (Eigen::Index i = 0; i < n; ++i) t.emplace_back(static_cast<int>(i), static_cast<int>(i), diag[i]);
    Eigen::SparseMatrix<double> expected(n, n);
    expected.setFromTriplets(t.begin(), t.end());
    ASSERT_TRUE(op.laplacian.isCompressed());
    EXPECT_EQ(op.laplacian.nonZeros(), expected.nonZeros());
    EXPECT_LT((op.laplacian - expected).norm(), 1e-13 * expected.norm());
    for (Eigen::Index c = 0; c < n; ++c)
      for (int p = op.laplacian.outerIndexPtr()[c] + 1; p < op.laplacian.outerIndexPtr()[c + 1]; ++p)
        EXPECT_LT(op.laplacian.innerIndexPtr()[p - 1], op.laplacian.innerIndexPtr()[p]);
    EXPECT_LT((op.laplacian * Eigen::VectorXd::Ones(n)).cwiseAbs().maxCoeff(), 1e-12 * diag.maxCoeff());
  }
}

// halfedge_connectivity + intrinsic_operator(…, connectivity, …): one connectivity serves every later operator of
// the same faces — on a moved surface, after an operator whose flips rewrote its own copy — and each comes out
// exactly as the operator built from the faces alone.
TEST(IntrinsicOperator, PrebuiltConnectivityGivesTheSameOperatorEveryTime) {
  Mesh mesh = testing::make_ellipsoid(1.0, 0.6, 2.0, 3);
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    mesh.vertices(i, 2) = 0.15 * std::round(mesh.vertices(i, 2) / 0.15);  // needles: the Delaunay operator flips
  const HalfedgeConnectivity connectivity = halfedge_connectivity(mesh.faces);
  ASSERT_EQ(connectivity.twin.size(), static_cast<std::size_t>(3 * mesh.face_count()));
  for (std::size_t h = 0; h < connectivity.twin.size(); ++h)
    ASSERT_EQ(connectivity.twin[static_cast<std::size_t>(connectivity.twin[h])], static_cast<int>(h));
  Eigen::MatrixX3d moved = mesh.vertices;
  moved.col(0) *= 1.7;  // another surface on the same faces
  for (const Eigen::MatrixX3d* x : {&mesh.vertices, &moved, &mesh.vertices})
    for (const LaplacianKind kind : {LaplacianKind::IntrinsicDelaunay, LaplacianKind::Mollified}) {
      const IntrinsicOperator fresh = intrinsic_operator(*x, mesh.faces, {kind});
      const IntrinsicOperator reused = intrinsic_operator(*x, mesh.faces, connectivity, {kind});
      if (kind == LaplacianKind::IntrinsicDelaunay && x == &mesh.vertices) {
        EXPECT_GT(reused.stats.flips, 0);
      }
      EXPECT_EQ(reused.stats.flips, fresh.stats.flips);
      EXPECT_EQ(reused.faces, fresh.faces);
      ASSERT_EQ(reused.laplacian.nonZeros(), fresh.laplacian.nonZeros());
      EXPECT_EQ((reused.laplacian - fresh.laplacian).norm(), 0.0);
      EXPECT_EQ(reused.mass, fresh.mass);
      EXPECT_EQ(reused.input_face_areas, fresh.input_face_areas);
      EXPECT_EQ(reused.input_cotangents, fresh.input_cotangents);
    }
}

TEST(IntrinsicOperator, ConnectivityOfOtherFacesOrOfAnOpenMeshIsRefused) {
  const Mesh mesh = testing::make_ellipsoid(1.0, 0.6, 2.0, 2);
  const Mesh other = testing::make_ellipsoid(1.0, 0.6, 2.0, 1);
  EXPECT_THROW(intrinsic_operator(mesh.vertices, mesh.faces, halfedge_connectivity(other.faces)), std::invalid_argument);
  const Eigen::MatrixX3i open = mesh.faces.topRows(mesh.face_count() - 1);
  try {
    (void)halfedge_connectivity(open);
    FAIL() << "an open mesh has an edge without opposite halfedge";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "not_closed");
  }
}

TEST(CotanLaplacian, ConstantsInKernelSymmetricPsd) {
  const Mesh mesh = testing::make_ellipsoid(1.0, 0.7, 0.5, 3);
  const Eigen::SparseMatrix<double> l = cotan_laplacian(mesh.vertices, mesh.faces);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.vertex_count());
  EXPECT_LT((l * ones).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((Eigen::SparseMatrix<double>(l.transpose()) - l).norm(), 1e-12);
  std::srand(testing::test_seed());
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd x = Eigen::VectorXd::Random(mesh.vertex_count());
    EXPECT_GE(x.dot(l * x), -1e-12);
  }
  // Dirichlet energy of the coordinate functions: ½ Σ xᵀLx = area for any closed surface... (Σ_k x_kᵀ L x_k = 2·area)
  const Eigen::MatrixX3d lx = l * mesh.vertices;
  const double dirichlet = (mesh.vertices.array() * lx.array()).sum();
  EXPECT_NEAR(dirichlet, 2.0 * face_areas(mesh.vertices, mesh.faces).sum(), 1e-9);
}

TEST(LumpedMass, SumsToArea) {
  const Mesh mesh = make_icosphere(3);
  const Eigen::VectorXd m = lumped_mass(mesh.vertices, mesh.faces);
  EXPECT_NEAR(m.sum(), face_areas(mesh.vertices, mesh.faces).sum(), 1e-12);
  EXPECT_GT(m.minCoeff(), 0.0);
}

TEST(VertexNormals, SphereNormalsAreRadial) {
  const Mesh mesh = make_icosphere(3);
  const Eigen::MatrixX3d n = vertex_normals(mesh.vertices, mesh.faces);
  EXPECT_LT((n - mesh.vertices).rowwise().norm().maxCoeff(), 1e-2);
  EXPECT_GT(signed_volume(mesh.vertices, mesh.faces), 4.0);
}

TEST(MeanCurvature, UnitIcosphereIsOneAndEnergyIsFourPi) {
  const Mesh mesh = make_icosphere(4);  // 2562 vertices
  const Eigen::VectorXd h = mean_curvature(mesh.vertices, mesh.faces);
  EXPECT_LT(std::abs(h.mean() - 1.0), 1e-2);
  EXPECT_GT(h.minCoeff(), 0.9);
  const double ratio = willmore_energy(mesh.vertices, mesh.faces) / (4.0 * std::numbers::pi);
  EXPECT_GE(ratio, 0.99);
  EXPECT_LE(ratio, 1.01);
}

TEST(MeanCurvature, ScalesInverselyWithLengthAndEnergyIsScaleInvariant) {
  Mesh mesh = testing::make_ellipsoid(1.0, 0.7, 0.5, 4);
  const Eigen::VectorXd h1 = mean_curvature(mesh.vertices, mesh.faces);
  const double e1 = willmore_energy(mesh.vertices, mesh.faces);
  mesh.vertices *= 3.0;
  const Eigen::VectorXd h3 = mean_curvature(mesh.vertices, mesh.faces);
  EXPECT_LT((h1 - 3.0 * h3).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(willmore_energy(mesh.vertices, mesh.faces), e1, 1e-9 * e1);
  EXPECT_GT(e1 / (4 * std::numbers::pi), 1.1);  // ellipsoid (1, 0.7, 0.5): ≈ 1.205
}

TEST(Roundness, SphereIsRoundEllipsoidIsNot) {
  const Mesh sphere = make_icosphere(3);
  EXPECT_LT(roundness(sphere.vertices, sphere.faces), 1e-12);
  const Mesh ellipsoid = testing::make_ellipsoid(1.0, 0.7, 0.5, 3);
  EXPECT_GT(roundness(ellipsoid.vertices, ellipsoid.faces), 0.1);
}

TEST(FaceGeometry, AnglesSumToPiAndCotangentsMatch) {
  const Mesh mesh = testing::make_ellipsoid(1.0, 0.7, 0.5, 2);
  const Eigen::MatrixX3d angles = corner_angles(mesh.vertices, mesh.faces);
  const Eigen::MatrixX3d cot = corner_cotangents(mesh.vertices, mesh.faces);
  EXPECT_LT((angles.rowwise().sum().array() - std::numbers::pi).abs().maxCoeff(), 1e-12);
  EXPECT_LT((angles.array().tan().inverse() - cot.array()).abs().maxCoeff(), 1e-9);
  EXPECT_GT(mean_edge_length(mesh.vertices, mesh.faces), 0.0);
}

}  // namespace
}  // namespace wish::geometry
