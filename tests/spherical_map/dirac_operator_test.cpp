// Algebra and operator identities (docs/design/spherical-map.md §4, §5, §9).
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/vertex_pattern.hpp"
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

// Lower-triangle storage read as Hermitian, both triangles (the convention of the stored Dirac pattern).
Eigen::SparseMatrix<std::complex<double>> hermitian_from_lower(const Eigen::SparseMatrix<std::complex<double>>& stored) {
  const Eigen::SparseMatrix<std::complex<double>> lower = stored.triangularView<Eigen::Lower>();
  const Eigen::SparseMatrix<std::complex<double>> strictly = stored.triangularView<Eigen::StrictlyLower>();
  return lower + Eigen::SparseMatrix<std::complex<double>>(strictly.adjoint());
}

TEST_F(DiracTest, PermutedPatternStoresThePermutedMatrixAndItsSolverGivesTheSameLambda) {
  // build_dirac_pattern with an order stores P𝔼Pᵀ (vertex order[k] at block k); a CHOLMOD solver that takes it as
  // prepermuted (natural ordering) finds the same smallest eigenvector, back in vertex order, as the unpermuted
  // matrix with a given ordering.
  std::mt19937 rng(testing::test_seed());
  std::uniform_real_distribution<double> u(-1, 1);
  for (Eigen::Index i = 0; i < rho.size(); ++i) rho[i] = u(rng);
  const geometry::VertexPattern vp = geometry::build_vertex_pattern(mesh.vertex_count(), mesh.faces);
  const Eigen::VectorXd areas = geometry::face_areas(mesh.vertices, mesh.faces);
  const std::vector<int> order = linalg::metis_ordering(vp.pattern);
  ASSERT_EQ(order.size(), static_cast<size_t>(mesh.vertex_count()));
  ComplexDiracPattern plain = build_dirac_pattern<std::complex<double>>(vp);
  ComplexDiracPattern permuted = build_dirac_pattern<std::complex<double>>(vp, order);
  const double d0 = assemble_dirac(vp, plain, mesh.vertices, mesh.faces, areas, rho);
  const double d1 = assemble_dirac(vp, permuted, mesh.vertices, mesh.faces, areas, rho);
  EXPECT_NEAR(d0, d1, 1e-14 * d0);
  // Only blocks on or below the block diagonal are stored (diagonal blocks whole).
  for (int c = 0; c < permuted.matrix.outerSize(); ++c)
    for (Eigen::SparseMatrix<std::complex<double>>::InnerIterator it(permuted.matrix, c); it; ++it)
      EXPECT_GE(it.row() / 2, c / 2);
  // P𝔼Pᵀ entry by entry: block k of the permuted matrix is vertex order[k].
  Eigen::VectorXi block_perm(2 * mesh.vertex_count());  // permuted index -> original index
  for (size_t k = 0; k < order.size(); ++k)
    for (int r = 0; r < 2; ++r) block_perm[2 * static_cast<int>(k) + r] = 2 * order[k] + r;
  const Eigen::MatrixXcd full_plain = Eigen::MatrixXcd(hermitian_from_lower(plain.matrix));
  const Eigen::MatrixXcd full_permuted = Eigen::MatrixXcd(hermitian_from_lower(permuted.matrix));
  double worst = 0;
  for (Eigen::Index a = 0; a < full_permuted.rows(); ++a)
    for (Eigen::Index b = 0; b < full_permuted.cols(); ++b)
      worst = std::max(worst, std::abs(full_permuted(a, b) - full_plain(block_perm[a], block_perm[b])));
  EXPECT_LT(worst, 1e-13 * full_plain.cwiseAbs().maxCoeff());

  linalg::CholeskyOptions given;
  given.cholmod_mode = linalg::CholmodMode::Supernodal;
  given.permutation = linalg::expand_ordering(order, 2);
  linalg::CholeskyOptions natural;
  natural.cholmod_mode = linalg::CholmodMode::Supernodal;
  natural.prepermuted = true;
  linalg::ComplexSparseCholesky given_solver(given), natural_solver(natural);
  Eigen::VectorXcd x_given, x_natural;
  const EigenSolveReport r_given = smallest_eigenvector(given_solver, plain.matrix, d0, EigenSolveOptions{}, x_given);
  const EigenSolveReport r_natural =
      smallest_eigenvector(natural_solver, permuted.matrix, d1, EigenSolveOptions{}, x_natural);
  ASSERT_TRUE(r_given.ok) << r_given.message;
  ASSERT_TRUE(r_natural.ok) << r_natural.message;
  EXPECT_EQ(given_solver.factor_nonzeros(), natural_solver.factor_nonzeros());  // the same ordering, no other
  const Eigen::VectorXd lambda_given = quaternions_from_complex(x_given);
  const Eigen::VectorXd lambda_natural = quaternions_from_complex(x_natural, order);
  EXPECT_LT((lambda_given - lambda_natural).norm(), 1e-10);
  EXPECT_LT(std::abs(r_given.rayleigh - r_natural.rayleigh), 1e-12);
  // The real 4V form unpermutes the same way.
  Eigen::VectorXd q_permuted(4 * mesh.vertex_count());
  for (size_t k = 0; k < order.size(); ++k) q_permuted.segment<4>(4 * k) = lambda_given.segment<4>(4 * order[k]);
  EXPECT_EQ(quaternions_from_permuted(q_permuted, order), lambda_given);
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
