// SH basis: reference values (Boost 1000-bit, mpmath 40-digit; tests/sh/data/README.md), orthonormality by
// quadrature, real <-> complex relations, stability to high degree, the shared cached instance.
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/errors.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_conversion.hpp"
#include "core/sh/sh_gram.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

// The committed reference rows beside this file (CMake compiles with absolute source paths).
const std::string kDataDir = std::filesystem::path(__FILE__).parent_path().string() + "/data/";

// Rows of a CSV, '#' comment lines and the header skipped, every field parsed as double.
std::vector<std::vector<double>> read_rows(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::vector<double>> rows;
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::vector<double> row;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, ',')) row.push_back(std::strtod(field.c_str(), nullptr));
    rows.push_back(row);
  }
  return rows;
}

// The agreement criterion: |ours - ref| <= 1e-12 |ref| + 1e-14 sqrt((2l+1)/4pi). The absolute floor (1e-14 of the
// degree's magnitude) only matters for values that vanish, e.g. sin(m p) at p = pi, where the double rounding of
// the tabulated decimal angle alone moves the value by ~1e-16 x l.
double allowed(double ref, int l) { return 1e-12 * std::abs(ref) + 1e-14 * std::sqrt((2.0 * l + 1) / (4 * M_PI)); }

TEST(ShBasis, MatchesBoostReference) {
  const auto rows = read_rows(kDataDir + "boost_sh_reference.csv");
  ASSERT_EQ(rows.size(), 242u);
  const auto basis = ShBasis::get(49);
  double worst_rel = 0;
  for (const auto& r : rows) {
    const int l = int(r[0]), m = int(r[1]);
    const Eigen::VectorXcd y = basis->complex(r[2], r[3]);
    const std::complex<double> v = y[sh_index(l, m)];
    const double scale = std::sqrt((2.0 * l + 1) / (4 * M_PI));
    EXPECT_LE(std::abs(v.real() - r[4]), allowed(r[4], l)) << "l=" << l << " m=" << m << " theta=" << r[2];
    EXPECT_LE(std::abs(v.imag() - r[5]), allowed(r[5], l)) << "l=" << l << " m=" << m << " theta=" << r[2];
    const double mag = std::hypot(r[4], r[5]);
    if (mag > 1e-3 * scale) worst_rel = std::max(worst_rel, std::abs(v - std::complex<double>(r[4], r[5])) / mag);
    // Negative order by symmetry: Y_l^{-m} = (-1)^m conj(Y_l^m).
    const std::complex<double> neg = y[sh_index(l, -m)];
    const std::complex<double> expect = (m % 2 ? -1.0 : 1.0) * std::conj(std::complex<double>(r[4], r[5]));
    EXPECT_LE(std::abs(neg - expect), allowed(mag, l));
  }
  std::printf("Boost rows: worst relative error where |Y| > 1e-3 sqrt((2l+1)/4pi): %.2e\n", worst_rel);
}

TEST(ShBasis, MatchesMpmathComplexAndRealIncludingPoles) {
  const auto rows = read_rows(kDataDir + "mpmath_sh_reference.csv");
  ASSERT_EQ(rows.size(), 784u);
  const auto basis = ShBasis::get(16);
  double worst_rel = 0;
  for (const auto& r : rows) {
    const int l = int(r[0]), m = int(r[1]);
    const Eigen::VectorXcd y = basis->complex(r[2], r[3]);
    const Eigen::VectorXd s = basis->real(r[2], r[3]);
    const std::complex<double> v = y[sh_index(l, m)];
    EXPECT_LE(std::abs(v.real() - r[4]), allowed(r[4], l)) << "l=" << l << " m=" << m << " theta=" << r[2];
    EXPECT_LE(std::abs(v.imag() - r[5]), allowed(r[5], l)) << "l=" << l << " m=" << m << " theta=" << r[2];
    EXPECT_LE(std::abs(s[sh_index(l, m)] - r[6]), allowed(r[6], l)) << "real l=" << l << " m=" << m;
    if (std::abs(r[6]) > 1e-8) worst_rel = std::max(worst_rel, std::abs(s[sh_index(l, m)] - r[6]) / std::abs(r[6]));
    // The same point given as a direction (poles: t = 0 and t = pi exactly as (0, 0, +-1)).
    const Eigen::Vector3d u(std::sin(r[2]) * std::cos(r[3]), std::sin(r[2]) * std::sin(r[3]), std::cos(r[2]));
    const Eigen::VectorXd su = basis->real(u);
    EXPECT_NEAR(su[sh_index(l, m)], r[6], 1e-13 * std::sqrt(2.0 * l + 1)) << "direction l=" << l << " m=" << m;
  }
  std::printf("mpmath rows: worst relative error of the real basis (|S| > 1e-8) %.2e\n", worst_rel);
}

TEST(ShBasis, PolesAreExact) {
  const auto basis = ShBasis::get(30);
  for (double zsign : {1.0, -1.0}) {
    const Eigen::VectorXd s = basis->real(Eigen::Vector3d(0, 0, zsign));
    for (int l = 0; l <= 30; ++l)
      for (int m = -l; m <= l; ++m) {
        const double expect = m == 0 ? std::pow(zsign, l) * std::sqrt((2.0 * l + 1) / (4 * M_PI)) : 0.0;
        EXPECT_NEAR(s[sh_index(l, m)], expect, 1e-13 * std::sqrt(2.0 * l + 1)) << l << " " << m;
      }
  }
}

TEST(ShBasis, OrthonormalByQuadrature) {
  // Gauss-Legendre in cos t (L+1 nodes, exact to degree 2L+1) x 2L+2 uniform azimuths: exact for products of
  // two harmonics of degree <= L.
  const int L = 16;
  Eigen::VectorXd z, w;
  gauss_legendre(L + 1, z, w);
  const int np = 2 * L + 2;
  Eigen::MatrixX3d pts(z.size() * np, 3);
  Eigen::VectorXd weights(pts.rows());
  for (Eigen::Index a = 0; a < z.size(); ++a)
    for (int b = 0; b < np; ++b) {
      const double s = std::sqrt(1 - z[a] * z[a]), p = 2 * M_PI * b / np;
      pts.row(a * np + b) << s * std::cos(p), s * std::sin(p), z[a];
      weights[a * np + b] = w[a] * 2 * M_PI / np;
    }
  const auto basis = ShBasis::get(L);
  const Eigen::MatrixXd Y = basis->real_matrix(pts);
  const Eigen::MatrixXd WY = Y.array().colwise() * weights.array();
  const Eigen::MatrixXd G = WY.transpose() * Y;
  EXPECT_LT((G - Eigen::MatrixXd::Identity(G.rows(), G.cols())).cwiseAbs().maxCoeff(), 1e-13);
  const Eigen::MatrixXcd Yc = basis->complex_matrix(pts);
  const Eigen::MatrixXcd WYc = Yc.array().colwise() * weights.cast<std::complex<double>>().array();
  const Eigen::MatrixXcd Gc = Yc.adjoint() * WYc;
  EXPECT_LT((Gc - Eigen::MatrixXcd::Identity(Gc.rows(), Gc.cols())).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(ShBasis, RealAndComplexRelations) {
  const auto basis = ShBasis::get(12);
  std::mt19937 rng(wish::testing::test_seed());
  std::normal_distribution<double> n(0, 1);
  for (int t = 0; t < 20; ++t) {
    const Eigen::Vector3d u(n(rng), n(rng), n(rng));
    const Eigen::VectorXd s = basis->real(u);
    const Eigen::VectorXcd y = basis->complex(u);
    for (int l = 0; l <= 12; ++l) {
      EXPECT_NEAR(s[sh_index(l, 0)], y[sh_index(l, 0)].real(), 1e-15);
      for (int m = 1; m <= l; ++m) {
        const double sign = m % 2 ? -1.0 : 1.0;
        EXPECT_NEAR(s[sh_index(l, m)], std::sqrt(2.0) * sign * y[sh_index(l, m)].real(), 1e-14);
        EXPECT_NEAR(s[sh_index(l, -m)], std::sqrt(2.0) * sign * y[sh_index(l, m)].imag(), 1e-14);
        EXPECT_LT(std::abs(y[sh_index(l, -m)] - sign * std::conj(y[sh_index(l, m)])), 1e-15);
      }
    }
    // S_1^1 = +sqrt(3/4pi) x (CS phase cancelled in the real basis), S_1^{-1} ~ y, S_1^0 ~ z.
    const Eigen::Vector3d d = u.normalized();
    const double c1 = std::sqrt(3 / (4 * M_PI));
    EXPECT_NEAR(s[sh_index(1, 1)], c1 * d.x(), 1e-15);
    EXPECT_NEAR(s[sh_index(1, -1)], c1 * d.y(), 1e-15);
    EXPECT_NEAR(s[sh_index(1, 0)], c1 * d.z(), 1e-15);
    // Coefficient conversion: a real field has the same values in both bases.
    Eigen::MatrixXd a(basis->size(), 2);
    for (Eigen::Index j = 0; j < a.size(); ++j) a.data()[j] = n(rng);
    const Eigen::MatrixXcd c = real_to_complex_coefficients(a);
    const std::complex<double> fc = (y.transpose() * c.col(0))(0);
    EXPECT_NEAR(fc.real(), s.dot(a.col(0)), 1e-12);
    EXPECT_NEAR(fc.imag(), 0.0, 1e-12);
    EXPECT_LT((complex_to_real_coefficients(c) - a).cwiseAbs().maxCoeff(), 1e-15);
    for (int l = 0; l <= 12; ++l)
      EXPECT_NEAR(c.col(1).segment(sh_index(l, -l), 2 * l + 1).squaredNorm(),
                  a.col(1).segment(sh_index(l, -l), 2 * l + 1).squaredNorm(), 1e-12);
  }
}

TEST(ShBasis, StableToHighDegree) {
  // Addition theorem (Unsold): sum_m S_l^m(u)^2 = (2l+1)/(4 pi) at every u — checks every order of every degree,
  // including near the poles where sin^m t underflows. Tolerance 1e-13 + 1e-16 l^2: near a pole, the rounding of
  // cos t (1e-16 absolute) moves P_l by up to |P_l'| 1e-16 ~ l^2/2 1e-16 relative (measured 4e-11 at l = 1000,
  // t = pi - 1e-6); it is the conditioning of the input, not growth in the recurrence.
  for (int L : {100, 300, 1000}) {
    const auto basis = ShBasis::get(L);
    const double thetas[] = {0.0, 1e-9, 1e-3, 0.3, M_PI / 2, 2.0, M_PI - 1e-6, M_PI};
    for (double t : thetas) {
      const Eigen::VectorXd s = basis->real(t, 0.7);
      ASSERT_TRUE(s.allFinite()) << "L=" << L << " theta=" << t;
      for (int l = 0; l <= L; l += (L > 100 ? 7 : 1)) {
        const double sum = s.segment(sh_index(l, -l), 2 * l + 1).squaredNorm();
        EXPECT_NEAR(sum / ((2.0 * l + 1) / (4 * M_PI)), 1.0, 1e-13 + 1e-16 * l * l)
            << "L=" << L << " l=" << l << " theta=" << t;
      }
    }
  }
}

TEST(ShBasis, MatrixProjectSynthesizeAgree) {
  const int L = 9;
  const auto basis = ShBasis::get(L);
  std::mt19937 rng(wish::testing::test_seed());
  std::normal_distribution<double> n(0, 1);
  Eigen::MatrixX3d pts(203, 3);  // not a multiple of the block size
  for (Eigen::Index i = 0; i < pts.size(); ++i) pts.data()[i] = n(rng);
  pts.row(5) << 0, 0, 2;  // a pole
  const Eigen::MatrixXd Y = basis->real_matrix(pts);
  for (Eigen::Index i = 0; i < pts.rows(); i += 17)
    EXPECT_LT((Y.row(i).transpose() - basis->real(Eigen::Vector3d(pts.row(i)))).cwiseAbs().maxCoeff(), 1e-15);
  Eigen::MatrixXd V(pts.rows(), 5), C(basis->size(), 3);
  for (Eigen::Index i = 0; i < V.size(); ++i) V.data()[i] = n(rng);
  for (Eigen::Index i = 0; i < C.size(); ++i) C.data()[i] = n(rng);
  EXPECT_LT((basis->project(pts, V) - Y.transpose() * V).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((basis->synthesize(pts, C) - Y * C).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ShBasis, SharedInstanceIsThreadSafe) {
  std::vector<std::shared_ptr<const ShBasis>> got(8);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) threads.emplace_back([&, t] { got[t] = ShBasis::get(33); });
  for (auto& th : threads) th.join();
  for (const auto& p : got) EXPECT_EQ(p.get(), got[0].get());
  EXPECT_EQ(got[0]->size(), 34 * 34);
  EXPECT_THROW(ShBasis::get(-1), InvalidInputError);
  EXPECT_THROW(ShBasis::get(kShMaxBasisLmax + 1), InvalidInputError);
  EXPECT_EQ(sh_degree(0), 0);
  EXPECT_EQ(sh_degree(sh_index(7, -7)), 7);
  EXPECT_EQ(sh_degree(sh_index(7, 7)), 7);
  EXPECT_EQ(sh_lmax_from_count(16), 3);
  EXPECT_THROW(sh_lmax_from_count(15), InvalidInputError);
}

}  // namespace
}  // namespace wish
