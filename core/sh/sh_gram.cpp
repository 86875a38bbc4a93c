#include "core/sh/sh_gram.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "core/common/errors.hpp"
#include "core/sh/sh_basis.hpp"

namespace wish {

void gauss_legendre(int n, Eigen::VectorXd& nodes, Eigen::VectorXd& weights) {
  nodes.resize(n);
  weights.resize(n);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 0;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1, p1 = 0;
      for (int k = 1; k <= n; ++k) {  // P_k(x) = ((2k-1) x P_{k-1} - (k-1) P_{k-2}) / k
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p2) / k;
      }
      dp = n * (x * p0 - p1) / (x * x - 1.0);
      const double dx = p0 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    {  // final derivative at the converged node
      double p0 = 1, p1 = 0;
      for (int k = 1; k <= n; ++k) {
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p2) / k;
      }
      dp = n * (x * p0 - p1) / (x * x - 1.0);
    }
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    nodes[i] = -x;
    nodes[n - 1 - i] = x;
    weights[i] = weights[n - 1 - i] = w;
  }
  if (n % 2) nodes[n / 2] = 0.0;
}

namespace {

// Per-Lmax tables of the quadrature path: nodes, weights, p_{l,b}(z_a) per order b (rows: nodes, columns:
// l = b..L; including the sqrt2 of the real basis for b > 0), and the degree-2L table at the nodes.
struct GramPlan {
  int lmax = 0, nodes = 0;
  Eigen::VectorXd z, w;
  std::vector<Eigen::MatrixXd> P;  // P[b]: nodes x (L+1-b)
  Eigen::MatrixXd T2;              // nodes x (2L+1)^2: S_J(t_a, p = 0) of degree <= 2L (zero for negative orders)

  explicit GramPlan(int L) : lmax(L), nodes(2 * L + 1) {
    gauss_legendre(nodes, z, w);
    const auto basis2 = ShBasis::get(2 * L);
    T2.resize(nodes, basis2->size());
    Eigen::VectorXd row(basis2->size());
    for (int a = 0; a < nodes; ++a) {
      basis2->evaluate_real(z[a], std::sqrt(std::max(0.0, 1.0 - z[a] * z[a])), 1.0, 0.0, row.data());
      T2.row(a) = row.transpose();
    }
    P.resize(L + 1);
    for (int b = 0; b <= L; ++b) {
      P[b].resize(nodes, L + 1 - b);
      for (int l = b; l <= L; ++l) P[b].col(l - b) = T2.col(sh_index(l, b));
    }
  }

  static std::shared_ptr<const GramPlan> get(int L) {
    static std::mutex mutex;
    static std::map<int, std::shared_ptr<const GramPlan>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = cache[L];
    if (!slot) slot = std::make_shared<const GramPlan>(L);
    return slot;
  }
};

Eigen::MatrixXd gram_quadrature(int L, const Eigen::MatrixX3d& points, const Eigen::VectorXd& weights) {
  const auto plan = GramPlan::get(L);
  const int N = plan->nodes, L2 = 2 * L, k = sh_count(L);
  const Eigen::VectorXd mu = ShBasis::get(L2)->project(points, weights);  // degree-2L moments

  // Fourier coefficients of g on ring a: g = sum_M A(a,M) cos(M p) + B(a,M) sin(M p), M = 0..2L.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N, L2 + 1), B = Eigen::MatrixXd::Zero(N, L2 + 1);
  for (int J = 0; J <= L2; ++J)
    for (int M = 0; M <= J; ++M) {
      const double mp = mu[sh_index(J, M)], mn = M > 0 ? mu[sh_index(J, -M)] : 0.0;
      for (int a = 0; a < N; ++a) {
        const double p = plan->T2(a, sh_index(J, M));
        A(a, M) += mp * p;
        B(a, M) += mn * p;
      }
    }
  // C(q) = int cos(q p) g dp,  Sn(q) = int sin(q p) g dp, q = -2L..2L (column q + 2L), per ring.
  Eigen::MatrixXd C(N, 2 * L2 + 1), Sn(N, 2 * L2 + 1);
  for (int q = -L2; q <= L2; ++q) {
    const int aq = std::abs(q);
    C.col(q + L2) = (q == 0 ? 2.0 * M_PI : M_PI) * A.col(aq);
    Sn.col(q + L2) = q == 0 ? Eigen::VectorXd::Zero(N) : Eigen::VectorXd(((q > 0) ? M_PI : -M_PI) * B.col(aq));
  }

  Eigen::MatrixXd G(k, k);
  // Block of signed orders (m, mp): G[(l,m),(l',mp)] = sum_a P[|m|](a,l) w_a Phi_a(m,mp) P[|mp|](a,l').
#pragma omp parallel for schedule(dynamic, 1) if (L >= 12)
  for (int m = -L; m <= L; ++m) {
    Eigen::VectorXd d(N);
    Eigen::MatrixXd left, blk;
    const int a = std::abs(m);
    for (int mp = -L; mp <= m; ++mp) {
      const int b = std::abs(mp);
      const int dif = a - b + L2, sum = a + b + L2;
      if (m >= 0 && mp >= 0)
        d = 0.5 * (C.col(dif) + C.col(sum));
      else if (m < 0 && mp < 0)
        d = 0.5 * (C.col(dif) - C.col(sum));
      else if (m >= 0)  // cos(a p) sin(b p)
        d = 0.5 * (Sn.col(sum) - Sn.col(dif));
      else  // sin(a p) cos(b p)
        d = 0.5 * (Sn.col(sum) + Sn.col(dif));
      d.array() *= plan->w.array();
      left = plan->P[a].transpose() * d.asDiagonal();
      blk.noalias() = left * plan->P[b];
      for (int l = a; l <= L; ++l)
        for (int lp = b; lp <= L; ++lp) {
          const double v = blk(l - a, lp - b);
          G(sh_index(l, m), sh_index(lp, mp)) = v;
          G(sh_index(lp, mp), sh_index(l, m)) = v;
        }
    }
  }
  return G;
}

Eigen::MatrixXd gram_product(int L, const Eigen::MatrixX3d& points, const Eigen::VectorXd& weights) {
  Eigen::MatrixXd Y = ShBasis::get(L)->real_matrix(points);
  Y.array().colwise() *= weights.array().sqrt();
  const Eigen::Index k = Y.cols();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(k, k);
  G.selfadjointView<Eigen::Lower>().rankUpdate(Y.transpose());
  G.triangularView<Eigen::StrictlyUpper>() = G.transpose();
  return G;
}

}  // namespace

Eigen::MatrixXd sh_gram_matrix(int lmax, const Eigen::MatrixX3d& points, const Eigen::VectorXd& weights,
                               GramMethod method) {
  if (weights.size() != points.rows())
    throw InvalidInputError("invalid_parameter", "Gram matrix: " + std::to_string(weights.size()) +
                                                     " weights for " + std::to_string(points.rows()) + " points");
  if ((weights.array() < 0).any())
    throw InvalidInputError("invalid_parameter", "Gram matrix: negative weight");
  if (method == GramMethod::Product) return gram_product(lmax, points, weights);
  return gram_quadrature(lmax, points, weights);
}

}  // namespace wish
