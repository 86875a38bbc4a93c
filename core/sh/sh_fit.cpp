#include "core/sh/sh_fit.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "core/common/errors.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_conversion.hpp"
#include "core/sh/sh_gram.hpp"
#include "core/sh/sh_invariants.hpp"
#include "core/sh/surface_quadrature.hpp"

namespace wish {
namespace {

void check_options(const ShFitOptions& o) {
  if (o.lmax < kShMinFitLmax)
    throw InvalidInputError("invalid_parameter",
                            "lmax " + std::to_string(o.lmax) + " is below the minimum " + std::to_string(kShMinFitLmax),
                            {{"lmax", std::int64_t{o.lmax}}});
  if (o.lmax > kShMaxFitLmax)
    throw LimitExceededError("lmax " + std::to_string(o.lmax) + " exceeds the limit " + std::to_string(kShMaxFitLmax),
                             {{"limit", std::string("lmax")},
                              {"value", std::int64_t{o.lmax}},
                              {"allowed", std::int64_t{kShMaxFitLmax}}});
  if (!std::isfinite(o.regularization) || o.regularization < 0)
    throw InvalidInputError("invalid_parameter", "regularization must be finite and >= 0",
                            {{"regularization", o.regularization}});
  if (o.band_size < 1)
    throw InvalidInputError("invalid_parameter", "band_size must be >= 1",
                            {{"band_size", std::int64_t{o.band_size}}});
}

void check_points(const Eigen::MatrixX3d& sphere_points, Eigen::Index n) {
  if (sphere_points.rows() != n)
    throw InvalidInputError("invalid_parameter",
                            "the sphere map has " + std::to_string(sphere_points.rows()) + " points for " +
                                std::to_string(n) + " vertices",
                            {{"sphere_points", std::int64_t{sphere_points.rows()}}, {"vertices", std::int64_t{n}}});
  if (n == 0) throw InvalidInputError("empty_mesh", "cannot fit spherical harmonics to zero points");
  for (Eigen::Index i = 0; i < n; ++i) {
    const double r = sphere_points.row(i).norm();
    if (!std::isfinite(r) || r == 0)
      throw InvalidInputError("invalid_parameter", "sphere point " + std::to_string(i) + " is zero or not finite",
                              {{"vertex", std::int64_t{i}}});
  }
}

// Penalty diagonal R_jj = l_j^2 (l_j + 1)^2 (the paper's Eq. 13 prints l^2 (l^2+1)^2: a typo).
double penalty(int l) { return double(l) * l * (l + 1.0) * (l + 1.0); }

// nu is given in the paper's units: the paper adds nu R to the *unweighted* normal equations Y^H Y of its ~10^4-vertex
// nuclei, whose Gram matrix is ~ n/(4 pi) I. Our weights sum to 1 (Gram ~ I/(4 pi), the same at every resolution),
// so the same relative damping is nu / n_paper. Using nu = 1e-5 directly with unit-sum weights would damp every
// degree above ~9 (measured: the fit error stops falling at Lmax ~ 8), contradicting the paper's Fig. 6.
constexpr double kPaperVertexCount = 1e4;
double penalty_weight(const ShFitOptions& o) { return o.regularization / kPaperVertexCount; }

Eigen::MatrixXd solve_ldlt(Eigen::MatrixXd& A, const Eigen::MatrixXd& rhs) {
  Eigen::LDLT<Eigen::MatrixXd, Eigen::Lower> ldlt(A);
  if (ldlt.info() != Eigen::Success)
    throw WishError(ErrorCategory::Internal, "fit_failed", "LDLT factorisation of the SH normal equations failed");
  Eigen::MatrixXd C = ldlt.solve(rhs);
  if (!C.allFinite())
    throw WishError(ErrorCategory::Internal, "fit_failed", "the SH normal equations are singular");
  return C;
}

Eigen::MatrixX3d solve_direct(const Eigen::MatrixX3d& points, const Eigen::MatrixX3d& X, const Eigen::VectorXd& w,
                              const ShFitOptions& o) {
  const int L = o.lmax, k = sh_count(L);
  Eigen::MatrixXd A = sh_gram_matrix(L, points, w, o.gram);
  for (int j = 0; j < k; ++j) A(j, j) += penalty_weight(o) * penalty(sh_degree(j));
  const Eigen::MatrixXd rhs = ShBasis::get(L)->project(points, X.array().colwise() * w.array());
  return solve_ldlt(A, rhs);
}

// The paper's residual scheme: bands of whole degrees [l0, l1] with at most band_size coefficients (a single
// degree with more functions forms a band alone); band s is fitted to the residual left by bands < s.
Eigen::MatrixX3d solve_banded(const Eigen::MatrixX3d& points, const Eigen::MatrixX3d& X, const Eigen::VectorXd& w,
                              const ShFitOptions& o) {
  const int L = o.lmax, k = sh_count(L);
  std::vector<std::pair<int, int>> bands;
  for (int l0 = 0; l0 <= L;) {
    int l1 = l0;
    while (l1 + 1 <= L && sh_count(l1 + 1) - sh_count(l0 - 1) <= o.band_size) ++l1;
    bands.emplace_back(l0, l1);
    l0 = l1 + 1;
  }
  const Eigen::MatrixXd G = sh_gram_matrix(L, points, w, o.gram);  // its diagonal blocks are the band Grams
  Eigen::MatrixX3d C = Eigen::MatrixX3d::Zero(k, 3);
  Eigen::MatrixX3d residual = X;
  for (const auto& [l0, l1] : bands) {
    const int j0 = sh_index(l0, -l0), kb = sh_count(l1) - j0;
    const auto basis = ShBasis::get(l1);
    Eigen::MatrixXd A = G.block(j0, j0, kb, kb);
    for (int j = 0; j < kb; ++j) A(j, j) += penalty_weight(o) * penalty(sh_degree(j0 + j));
    const Eigen::MatrixXd rhs = basis->project(points, residual.array().colwise() * w.array()).bottomRows(kb);
    const Eigen::MatrixXd Cb = solve_ldlt(A, rhs);
    C.middleRows(j0, kb) = Cb;
    Eigen::MatrixXd padded = Eigen::MatrixXd::Zero(basis->size(), 3);
    padded.bottomRows(kb) = Cb;
    residual -= basis->synthesize(points, padded);
  }
  return C;
}

}  // namespace

Eigen::VectorXd fit_weights(const Mesh& input, FitWeighting weighting) {
  const Eigen::Index n = input.vertex_count();
  if (n == 0) throw InvalidInputError("empty_mesh", "cannot fit spherical harmonics to a mesh without vertices");
  if (weighting == FitWeighting::Uniform) return Eigen::VectorXd::Constant(n, 1.0 / double(n));
  Eigen::VectorXd w = geometry::lumped_mass(input.vertices, input.faces);  // a third of each incident triangle
  const double total = w.sum();
  if (!(total > 0) || !std::isfinite(total))
    throw InvalidInputError("degenerate_mesh", "the mesh has zero total area; area weights are undefined",
                            {{"area", total}});
  return w / total;
}

Eigen::MatrixX3d fit_real_sh(const Eigen::MatrixX3d& sphere_points, const Eigen::MatrixX3d& targets,
                             const Eigen::VectorXd& weights, const ShFitOptions& options) {
  check_options(options);
  check_points(sphere_points, targets.rows());
  if (weights.size() != targets.rows() || (weights.array() < 0).any() || !weights.allFinite() ||
      !(weights.sum() > 0))
    throw InvalidInputError("invalid_parameter",
                            "fit weights must be n finite non-negative values with a positive sum");
  if (!targets.allFinite()) throw InvalidInputError("non_finite_vertex", "the fit targets contain NaN or Inf");
  if (options.regularization == 0 && targets.rows() < sh_count(options.lmax))
    throw InvalidInputError("invalid_parameter", "an unregularised fit needs at least (Lmax+1)^2 = " +
                                                     std::to_string(sh_count(options.lmax)) + " points; got " +
                                                     std::to_string(targets.rows()));
  const Eigen::VectorXd w = weights / weights.sum();
  return options.solver == FitSolver::Banded ? solve_banded(sphere_points, targets, w, options)
                                             : solve_direct(sphere_points, targets, w, options);
}

FitError sh_fit_error(const Eigen::MatrixX3d& sphere_points, const Eigen::MatrixX3d& targets,
                      const Eigen::MatrixX3d& real_coefficients) {
  FitError e;
  const Eigen::Index n = targets.rows();
  if (n == 0) return e;
  const auto basis = ShBasis::get(sh_lmax_from_count(real_coefficients.rows()));
  const Eigen::MatrixXd fitted = basis->synthesize(sphere_points, real_coefficients);
  const Eigen::VectorXd d = (targets - fitted).rowwise().norm();
  e.mean = d.mean();
  e.rms = std::sqrt(d.squaredNorm() / double(n));
  e.max = d.maxCoeff();
  const double diag = (targets.colwise().maxCoeff() - targets.colwise().minCoeff()).norm();
  if (diag > 0) {
    e.mean_relative = e.mean / diag;
    e.rms_relative = e.rms / diag;
    e.max_relative = e.max / diag;
  }
  return e;
}

ShDescriptor fit_spherical_harmonics(const Mesh& input, const Eigen::MatrixX3d& sphere_points,
                                     const ShFitOptions& options) {
  check_options(options);
  check_points(sphere_points, input.vertex_count());
  Eigen::MatrixX3d real;
  if (options.sampling == FitSampling::Surface) {
    const SurfaceSamples samples = surface_quadrature(input, sphere_points, options.lmax);
    if (!(samples.weights.sum() > 0))
      throw InvalidInputError("degenerate_mesh", "the mesh has zero total area; the surface fit is undefined");
    real = fit_real_sh(samples.sphere_points, samples.targets, samples.weights, options);
  } else {
    real = fit_real_sh(sphere_points, input.vertices, fit_weights(input, options.weighting), options);
  }
  ShDescriptor d;
  d.lmax = options.lmax;
  d.options = options;
  d.coefficients = real_to_complex_coefficients(real);
  d.invariants = sh_invariants_real(real);
  d.fit_error = sh_fit_error(sphere_points, input.vertices, real);
  return d;
}

}  // namespace wish
