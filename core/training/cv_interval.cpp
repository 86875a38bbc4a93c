#include "core/training/cv_interval.hpp"

#include <algorithm>
#include <cmath>

#include "core/common/errors.hpp"

namespace wish {
namespace {

// Continued fraction of the regularised incomplete beta function I_x(a, b) (modified Lentz; Numerical Recipes 6.4).
double beta_fraction(double a, double b, double x) {
  constexpr double tiny = 1e-300, eps = 1e-15;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  if (std::abs(d) < tiny) d = tiny;
  d = 1 / d;
  double h = d;
  for (int m = 1; m <= 1000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1) * (a + m2));
    d = 1 + aa * d;
    c = 1 + aa / c;
    d = 1 / (std::abs(d) < tiny ? tiny : d);
    c = std::abs(c) < tiny ? tiny : c;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1));
    d = 1 + aa * d;
    c = 1 + aa / c;
    d = 1 / (std::abs(d) < tiny ? tiny : d);
    c = std::abs(c) < tiny ? tiny : c;
    const double step = d * c;
    h *= step;
    if (std::abs(step - 1) < eps) break;
  }
  return h;
}

// I_x(a, b) with y = 1 - x given separately, so that x close to 1 keeps its precision.
double incomplete_beta(double a, double b, double x, double y) {
  if (x <= 0) return 0;
  if (y <= 0) return 1;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log(y));
  return x < (a + 1) / (a + b + 2) ? front * beta_fraction(a, b, x) / a : 1 - front * beta_fraction(b, a, y) / b;
}

// P(T <= t) for Student's t with df degrees of freedom: the tail is I_{v / (v + t^2)}(v / 2, 1 / 2) / 2.
double student_t_cdf(double t, int df) {
  const double v = df, t2 = t * t;
  const double tail = 0.5 * incomplete_beta(v / 2, 0.5, v / (v + t2), t2 / (v + t2));
  return t >= 0 ? 1 - tail : tail;
}

}  // namespace

double student_t_quantile(double p, int df) {
  if (!(p > 0 && p < 1) || df < 1)
    throw InvalidInputError("training_parameters", "Student's t quantile needs 0 < p < 1 and df >= 1");
  double lo = -1, hi = 1;
  while (student_t_cdf(lo, df) > p) lo *= 2;
  while (student_t_cdf(hi, df) < p) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * std::max(1.0, std::abs(lo)); ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_cdf(mid, df) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::optional<Interval> cv_interval(const std::vector<double>& scores, double test_over_train) {
  const std::size_t J = scores.size();
  if (J < 2) return std::nullopt;
  double mean = 0;
  for (double s : scores) mean += s;
  mean /= static_cast<double>(J);
  double var = 0;
  for (double s : scores) var += (s - mean) * (s - mean);
  var /= static_cast<double>(J - 1);
  const double half = student_t_quantile(0.975, static_cast<int>(J) - 1) *
                      std::sqrt((1.0 / static_cast<double>(J) + test_over_train) * var);
  return Interval{std::max(0.0, mean - half), std::min(1.0, mean + half)};
}

}  // namespace wish
