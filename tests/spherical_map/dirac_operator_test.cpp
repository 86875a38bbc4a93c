// Algebra and operator identities (docs/design/spherical-map.md §4, §5, §9).
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/linalg/sparse_cholesky.hpp"
#include "core/mesh/icosphere.hpp"
#include "core/spherical_map/dirac_operator.hpp"
#include "core/spherical_map/quaternion.hpp"
#include "core/spherical_map/spin_transform.hpp"
#include "tests/testing/test_data.hpp"

namespace wish::spherical {
namespace {

Quaternion random_quaternion(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return {n(rng), n(rng), n(rng), n(rng)};
}

TEST(Quaternion, BlockIsAnAlgebraHomomorphism) {
  std::mt19937 rng(testing::test_seed());
  for (int t = 0; t < 20; ++t) {
    const Quaternion p = random_quaternion(rng), q = random_quaternion(rng);
    EXPECT_LT((left_block(p) * left_block(q) - left_block(p * q)).norm(), 1e-12);
    EXPECT_LT((left_block(q.conj()) - left_block(q).transpose()).norm(), 1e-15);
    EXPECT_LT((left_block(p) * q.coeffs() - (p * q).coeffs()).norm(), 1e-12);
  }
  // i² = j² = k² = ijk = −1; imaginary u v = −u·v + u×v.
  const Quaternion i{0, 1, 0, 0}, j{0, 0, 1, 0}, k{0, 0, 0, 1};
  EXPECT_EQ((i * j * k).coeffs(), Eigen::Vector4d(-1, 0, 0, 0));
  EXPECT_EQ((i * j).coeffs(), k.coeffs());
  const Eigen::Vector3d u(1, 2, 3), v(-2, 0.5, 4);
  const Quaternion uv = Quaternion::imaginary(u) * Quaternion::imaginary(v);
  EXPECT_NEAR(uv.w, -u.dot(v), 1e-14);
  EXPECT_LT((uv.vec() - u.cross(v)).norm(), 1e-14);
}

class DiracTest : public ::testing::Test {
 protected:
  Mesh mesh = testing::make_ellipsoid(1.0, 0.7, 0.5, 2);
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(mesh.vertex_count());
};

TEST_F(DiracTest, SymmetricPsdWithConstantKernelAtZeroRho) {
  const Eigen::SparseMatrix<double> e0 = dirac_matrix(mesh.vertices, mesh.faces, rho);
  EXPECT_LT((Eigen::SparseMatrix<double>(e0.transpose()) - e0).norm(), 1e-12 * e0.norm());
  for (int c = 0; c < 4; ++c) {
    Eigen::VectorXd constant = Eigen::VectorXd::Zero(e0.rows());
    for (Eigen::Index i = c; i < constant.size(); i += 4) constant[i] = 1.0;
    EXPECT_LT((e0 * constant).norm(), 1e-12);
  }
  std::srand(testing::test_seed());
  rho = Eigen::VectorXd::Random(mesh.vertex_count());
  const Eigen::SparseMatrix<double> e = dirac_matrix(mesh.vertices, mesh.faces, rho);
  EXPECT_LT((Eigen::SparseMatrix<double>(e.transpose()) - e).norm(), 1e-12 * e.norm());
  for (int t = 0; t < 10; ++t) {
    const Eigen::VectorXd x = Eigen::VectorXd::Random(e.rows());
    EXPECT_GE(x.dot(e * x), -1e-12 * x.squaredNorm());
  }
}

TEST_F(DiracTest, ComplexHermitianFormMatchesRealForm) {
  std::srand(testing::test_seed());
  rho = Eigen::VectorXd::Random(mesh.vertex_count());
  const Eigen::SparseMatrix<double> e = dirac_matrix(mesh.vertices, mesh.faces, rho);
  const Eigen::SparseMatrix<std::complex<double>> z = dirac_matrix_complex(mesh.vertices, mesh.faces, rho);
  EXPECT_LT((Eigen::SparseMatrix<std::complex<double>>(z.adjoint()) - z).norm(), 1e-12 * z.norm());
  const Eigen::VectorXd x = Eigen::VectorXd::Random(e.rows());
  const Eigen::VectorXd ex = e * x;
  const Eigen::VectorXd zx = quaternions_from_complex(z * complex_from_quaternions(x));
  EXPECT_LT((ex - zx).norm(), 1e-12 * ex.norm());
  EXPECT_LT((quaternions_from_complex(complex_from_quaternions(x)) - x).norm(), 1e-15);
}

TEST_F(DiracTest, SmallestEigenvectorOfIntegrableChangeIsConstant) {
  // ρ = 0: the constants are the kernel; inverse iteration from λ ≡ 1 stays there (real and complex forms).
  const Eigen::SparseMatrix<double> e = dirac_matrix(mesh.vertices, mesh.faces, rho);
  linalg::SparseCholesky solver;
  Eigen::VectorXd x;
  const double mean_diag = e.diagonal().mean();
  const EigenSolveReport r = smallest_eigenvector(solver, e, mean_diag, EigenSolveOptions{}, x);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_LT(r.residual, 1e-8);
  EXPECT_LT(std::abs(r.rayleigh), 1e-10);
  const Eigen::SparseMatrix<std::complex<double>> z = dirac_matrix_complex(mesh.vertices, mesh.faces, rho);
  linalg::ComplexSparseCholesky csolver;
  Eigen::VectorXcd zx;
  const EigenSolveReport rc = smallest_eigenvector(csolver, z, mean_diag, EigenSolveOptions{}, zx);
  ASSERT_TRUE(rc.ok) << rc.message;
  EXPECT_LT((quaternions_from_complex(zx) - x).norm(), 1e-6);
}

// Positions from a λ field: divergence of transformed edges, pinned Poisson solve.
Eigen::MatrixX3d positions_from_lambda(const Mesh& mesh, const Eigen::VectorXd& lambda) {
  const Eigen::MatrixX3d cot = geometry::corner_cotangents(mesh.vertices, mesh.faces);
  const Eigen::SparseMatrix<double> l = geometry::cotan_laplacian(mesh.vertices, mesh.faces);
  Eigen::MatrixX3d omega = spin_divergence(mesh.vertices, mesh.faces, cot, lambda);
  omega.row(0).setZero();
  Eigen::SparseMatrix<double> pinned;
  pin_vertex(l, 0, pinned);
  linalg::SparseCholesky solver;
  EXPECT_TRUE(solver.factorize(pinned)) << solver.message();
  return solver.solve(omega);
}

TEST_F(DiracTest, ConstantLambdaReproducesScalesAndRotates) {
  const Eigen::Index n = mesh.vertex_count();
  const Eigen::MatrixX3d x0 = mesh.vertices.rowwise() - mesh.vertices.row(0);
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(4 * n);
  for (Eigen::Index i = 0; i < n; ++i) lambda[4 * i] = 1.0;
  EXPECT_LT((positions_from_lambda(mesh, lambda) - x0).cwiseAbs().maxCoeff(), 1e-10);
  lambda *= 1.5;  // λ ≡ c scales by c²
  EXPECT_LT((positions_from_lambda(mesh, lambda) - 2.25 * x0).cwiseAbs().maxCoeff(), 1e-10);
  std::mt19937 rng(testing::test_seed());
  Quaternion q = random_quaternion(rng);
  q = (1.0 / std::sqrt(q.norm2())) * q;
  for (Eigen::Index i = 0; i < n; ++i) lambda.segment<4>(4 * i) = q.coeffs();
  const Eigen::MatrixX3d rotated = positions_from_lambda(mesh, lambda);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d expected = (q.conj() * Quaternion::imaginary(x0.row(i)) * q).vec();
    EXPECT_LT((rotated.row(i).transpose() - expected).norm(), 1e-10);
  }
}

}  // namespace
}  // namespace wish::spherical
