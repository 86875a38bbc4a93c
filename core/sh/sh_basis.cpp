#include "core/sh/sh_basis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

#include "core/common/errors.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace wish {
namespace {

constexpr int kBlock = 64;                     // points per evaluation block (arrays stay in L1)
constexpr double kFlush = 1e-280;              // sectoral seeds below this are set to 0 (no denormals)
const double kY00 = 0.5 / std::sqrt(M_PI);     // Pbar_0^0 = 1 / sqrt(4 pi)
const double kSqrt2 = std::sqrt(2.0);

// Direction -> (cos t, sin t, cos p, sin p) of u / |u|. At the poles p is taken as 0.
inline void angles_of(double x, double y, double z, double& ct, double& st, double& cp, double& sp) {
  const double rho = std::hypot(x, y);
  const double r = std::hypot(rho, z);
  ct = z / r;
  st = rho / r;
  if (rho > 0) {
    cp = x / rho;
    sp = y / rho;
  } else {
    cp = 1;
    sp = 0;
  }
}

}  // namespace

int sh_degree(int j) {
  int l = static_cast<int>(std::sqrt(static_cast<double>(j)));
  while (l * l > j) --l;
  while ((l + 1) * (l + 1) <= j) ++l;
  return l;
}

int sh_lmax_from_count(Eigen::Index k) {
  const auto l = static_cast<Eigen::Index>(std::llround(std::sqrt(static_cast<double>(k))));
  if (k <= 0 || l * l != k)
    throw InvalidInputError("invalid_parameter",
                            "coefficient count " + std::to_string(k) + " is not (Lmax+1)^2 for an integer Lmax >= 0",
                            {{"count", std::int64_t{k}}});
  return static_cast<int>(l - 1);
}

std::shared_ptr<const ShBasis> ShBasis::get(int lmax) {
  static std::mutex mutex;
  static std::map<int, std::shared_ptr<const ShBasis>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[lmax];
  if (!slot) slot = std::make_shared<const ShBasis>(lmax);
  return slot;
}

ShBasis::ShBasis(int lmax) : lmax_(lmax) {
  if (lmax < 0 || lmax > kShMaxBasisLmax)
    throw InvalidInputError("invalid_parameter",
                            "spherical-harmonic degree " + std::to_string(lmax) + " is outside [0, " +
                                std::to_string(kShMaxBasisLmax) + "]",
                            {{"lmax", std::int64_t{lmax}}});
  const int n = lmax + 1;
  a_.setZero(n * n);
  b_.setZero(n * n);
  seed_.setZero(n);
  first_.setZero(n);
  for (int m = 0; m <= lmax; ++m) {
    seed_[m] = m == 0 ? kY00 : std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    first_[m] = std::sqrt(2.0 * m + 3.0);
    for (int l = m + 2; l <= lmax; ++l) {
      const double ll = l, mm = m;
      a_[l * n + m] = std::sqrt((4 * ll * ll - 1) / (ll * ll - mm * mm));
      b_[l * n + m] = std::sqrt(((ll - 1) * (ll - 1) - mm * mm) / (4 * (ll - 1) * (ll - 1) - 1));
    }
  }
}

// The kernel: for nb <= kBlock points given by (z, s, cos p, sin p), calls
//   emit(l, m, p, tc, ts)   for m = 0..L, l = m..L,
// where p[i] = Pbar_l^m(z_i) (complex normalisation, no CS phase) and tc/ts = f_m {cos, sin}(m p_i),
// f_0 = 1, f_m = sqrt2: the real basis is S_l^m = p tc, S_l^{-m} = p ts. Loops over points are innermost
// (vectorised by the compiler).
template <class Emit>
void ShBasis::run_block(int nb, const double* z, const double* s, const double* cp, const double* sp,
                        Emit&& emit) const {
  alignas(64) double pmm[kBlock], cm[kBlock], sm[kBlock], tc[kBlock], ts[kBlock];
  alignas(64) double buf0[kBlock], buf1[kBlock], buf2[kBlock];
  const int L = lmax_;
  const int n = L + 1;
  for (int i = 0; i < nb; ++i) {
    pmm[i] = kY00;
    cm[i] = 1;
    sm[i] = 0;
    tc[i] = 1;
    ts[i] = 0;
  }
  for (int m = 0; m <= L; ++m) {
    if (m > 0) {
      const double sd = seed_[m];
      for (int i = 0; i < nb; ++i) {
        const double v = pmm[i] * sd * s[i];
        pmm[i] = std::abs(v) < kFlush ? 0.0 : v;
        const double c = cm[i] * cp[i] - sm[i] * sp[i];
        const double t = sm[i] * cp[i] + cm[i] * sp[i];
        cm[i] = c;
        sm[i] = t;
        tc[i] = kSqrt2 * c;
        ts[i] = kSqrt2 * t;
      }
    }
    emit(m, m, static_cast<const double*>(pmm), static_cast<const double*>(tc), static_cast<const double*>(ts));
    if (m == L) break;
    double* p2 = buf0;  // Pbar_{l-2}
    double* p1 = buf1;  // Pbar_{l-1}
    double* p0 = buf2;
    const double f = first_[m];
    for (int i = 0; i < nb; ++i) {
      p2[i] = pmm[i];
      p1[i] = f * z[i] * pmm[i];
    }
    emit(m + 1, m, static_cast<const double*>(p1), static_cast<const double*>(tc), static_cast<const double*>(ts));
    for (int l = m + 2; l <= L; ++l) {
      const double a = a_[l * n + m], b = b_[l * n + m];
#pragma omp simd
      for (int i = 0; i < nb; ++i) p0[i] = a * (z[i] * p1[i] - b * p2[i]);
      emit(l, m, static_cast<const double*>(p0), static_cast<const double*>(tc), static_cast<const double*>(ts));
      double* t = p2;
      p2 = p1;
      p1 = p0;
      p0 = t;
    }
  }
}

// Runs the kernel on rows [begin, end) of `points`, block by block; emit(i0, nb, l, m, p, tc, ts).
template <class Emit>
void ShBasis::run_points(const Eigen::MatrixX3d& points, Eigen::Index begin, Eigen::Index end, Emit&& emit) const {
  alignas(64) double z[kBlock], s[kBlock], cp[kBlock], sp[kBlock];
  for (Eigen::Index i0 = begin; i0 < end; i0 += kBlock) {
    const int nb = static_cast<int>(std::min<Eigen::Index>(kBlock, end - i0));
    for (int i = 0; i < nb; ++i)
      angles_of(points(i0 + i, 0), points(i0 + i, 1), points(i0 + i, 2), z[i], s[i], cp[i], sp[i]);
    run_block(nb, z, s, cp, sp, [&](int l, int m, const double* p, const double* tc, const double* ts) {
      emit(i0, nb, l, m, p, tc, ts);
    });
  }
}

void ShBasis::evaluate_real(double cos_t, double sin_t, double cos_p, double sin_p, double* out) const {
  run_block(1, &cos_t, &sin_t, &cos_p, &sin_p,
            [&](int l, int m, const double* p, const double* tc, const double* ts) {
              out[sh_index(l, m)] = p[0] * tc[0];
              if (m > 0) out[sh_index(l, -m)] = p[0] * ts[0];
            });
}

Eigen::VectorXd ShBasis::real(double theta, double phi) const {
  Eigen::VectorXd out(size());
  evaluate_real(std::cos(theta), std::sin(theta), std::cos(phi), std::sin(phi), out.data());
  return out;
}

Eigen::VectorXd ShBasis::real(const Eigen::Vector3d& u) const {
  double ct, st, cp, sp;
  angles_of(u.x(), u.y(), u.z(), ct, st, cp, sp);
  Eigen::VectorXd out(size());
  evaluate_real(ct, st, cp, sp, out.data());
  return out;
}

namespace {
// Complex values from the real ones of the same point: for m > 0,
//   Y_l^m = (-1)^m (S_l^m + i S_l^{-m}) / sqrt2,  Y_l^{-m} = (S_l^m - i S_l^{-m}) / sqrt2.
Eigen::VectorXcd complex_from_real(const Eigen::VectorXd& r, int lmax) {
  Eigen::VectorXcd out(r.size());
  const double h = 1.0 / std::sqrt(2.0);
  for (int l = 0; l <= lmax; ++l) {
    out[sh_index(l, 0)] = r[sh_index(l, 0)];
    for (int m = 1; m <= l; ++m) {
      const double re = r[sh_index(l, m)] * h, im = r[sh_index(l, -m)] * h;
      const double sign = (m % 2) ? -1.0 : 1.0;
      out[sh_index(l, m)] = {sign * re, sign * im};
      out[sh_index(l, -m)] = {re, -im};
    }
  }
  return out;
}
}  // namespace

Eigen::VectorXcd ShBasis::complex(double theta, double phi) const { return complex_from_real(real(theta, phi), lmax_); }
Eigen::VectorXcd ShBasis::complex(const Eigen::Vector3d& u) const { return complex_from_real(real(u), lmax_); }

Eigen::MatrixXd ShBasis::real_matrix(const Eigen::MatrixX3d& points) const {
  const Eigen::Index n = points.rows();
  Eigen::MatrixXd Y(n, size());
  const Eigen::Index blocks = (n + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(static) if (blocks > 4 && n * size() > 200000)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    run_points(points, b * kBlock, std::min(n, (b + 1) * kBlock),
               [&](Eigen::Index i0, int nb, int l, int m, const double* p, const double* tc, const double* ts) {
                 double* col = Y.col(sh_index(l, m)).data() + i0;
                 for (int i = 0; i < nb; ++i) col[i] = p[i] * tc[i];
                 if (m > 0) {
                   double* neg = Y.col(sh_index(l, -m)).data() + i0;
                   for (int i = 0; i < nb; ++i) neg[i] = p[i] * ts[i];
                 }
               });
  }
  return Y;
}

Eigen::MatrixXcd ShBasis::complex_matrix(const Eigen::MatrixX3d& points) const {
  const Eigen::MatrixXd R = real_matrix(points);
  Eigen::MatrixXcd C(R.rows(), R.cols());
  const double h = 1.0 / std::sqrt(2.0);
  for (int l = 0; l <= lmax_; ++l) {
    C.col(sh_index(l, 0)) = R.col(sh_index(l, 0)).cast<std::complex<double>>();
    for (int m = 1; m <= l; ++m) {
      const double sign = (m % 2) ? -1.0 : 1.0;
      C.col(sh_index(l, m)).real() = sign * h * R.col(sh_index(l, m));
      C.col(sh_index(l, m)).imag() = sign * h * R.col(sh_index(l, -m));
      C.col(sh_index(l, -m)).real() = h * R.col(sh_index(l, m));
      C.col(sh_index(l, -m)).imag() = -h * R.col(sh_index(l, -m));
    }
  }
  return C;
}

Eigen::MatrixXd ShBasis::project(const Eigen::MatrixX3d& points, const Eigen::MatrixXd& values) const {
  if (values.rows() != points.rows())
    throw InvalidInputError("invalid_parameter", "project: values and points differ in row count");
  const Eigen::Index n = points.rows();
  const int c = static_cast<int>(values.cols());
  const int k = size();
  const Eigen::Index blocks = (n + kBlock - 1) / kBlock;
  Eigen::MatrixXd total = Eigen::MatrixXd::Zero(k, c);
  // Each thread sums a contiguous range of blocks; partial sums are added in thread order (deterministic for a
  // given thread count).
#pragma omp parallel if (blocks > 8 && n * k > 400000)
  {
    int threads = 1, id = 0;
#ifdef _OPENMP
    threads = omp_get_num_threads();
    id = omp_get_thread_num();
#endif
    Eigen::MatrixXd acc = Eigen::MatrixXd::Zero(k, c);
    const Eigen::Index b0 = blocks * id / threads, b1 = blocks * (id + 1) / threads;
    alignas(64) double wc[4][kBlock], ws[4][kBlock];
    for (int q0 = 0; q0 < c; q0 += 4) {
      const int qc = std::min(4, c - q0);
      for (Eigen::Index b = b0; b < b1; ++b) {
        const Eigen::Index begin = b * kBlock, end = std::min(n, (b + 1) * kBlock);
        run_points(points, begin, end,
                   [&](Eigen::Index i0, int nb, int l, int m, const double* p, const double* tc, const double* ts) {
                     if (l == m) {  // new order m: weight the trigonometric factors once
                       for (int q = 0; q < qc; ++q) {
                         const double* v = values.col(q0 + q).data() + i0;
                         for (int i = 0; i < nb; ++i) {
                           wc[q][i] = tc[i] * v[i];
                           ws[q][i] = ts[i] * v[i];
                         }
                       }
                     }
                     const int jp = sh_index(l, m), jn = sh_index(l, -m);
                     for (int q = 0; q < qc; ++q) {
                       double sc = 0, ss = 0;
#pragma omp simd reduction(+ : sc, ss)
                       for (int i = 0; i < nb; ++i) {
                         sc += p[i] * wc[q][i];
                         ss += p[i] * ws[q][i];
                       }
                       acc(jp, q0 + q) += sc;
                       if (m > 0) acc(jn, q0 + q) += ss;
                     }
                   });
      }
    }
#pragma omp for ordered schedule(static, 1)
    for (int t = 0; t < threads; ++t) {
#pragma omp ordered
      total += acc;
    }
  }
  return total;
}

Eigen::MatrixXd ShBasis::synthesize(const Eigen::MatrixX3d& points, const Eigen::MatrixXd& coefficients) const {
  if (coefficients.rows() != size())
    throw InvalidInputError("invalid_parameter", "synthesize: coefficient rows " +
                                                     std::to_string(coefficients.rows()) + " != (Lmax+1)^2 = " +
                                                     std::to_string(size()));
  const Eigen::Index n = points.rows();
  const int c = static_cast<int>(coefficients.cols());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, c);
  const Eigen::Index blocks = (n + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(static) if (blocks > 4 && n * size() > 200000)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    run_points(points, b * kBlock, std::min(n, (b + 1) * kBlock),
               [&](Eigen::Index i0, int nb, int l, int m, const double* p, const double* tc, const double* ts) {
                 const int jp = sh_index(l, m), jn = sh_index(l, -m);
                 for (int q = 0; q < c; ++q) {
                   const double cpos = coefficients(jp, q), cneg = m > 0 ? coefficients(jn, q) : 0.0;
                   double* o = out.col(q).data() + i0;
                   for (int i = 0; i < nb; ++i) o[i] += p[i] * (cpos * tc[i] + cneg * ts[i]);
                 }
               });
  }
  return out;
}

}  // namespace wish
