/// @file chi2.cpp
/// @brief chi2 quantiles by bisection on the regularized incomplete gamma function.
#include "vio_core/chi2.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vid {

namespace {

/// Regularized lower incomplete gamma P(a, x): series below a + 1, continued fraction above.
double gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_pre = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_pre);
  }
  // Modified Lentz evaluation of the continued fraction for Q(a, x).
  const double tiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double f = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    f *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_pre) * f;
}

constexpr int kTableSize = 257;

}  // namespace

double chi2_quantile(double p, int dof) {
  if (!(p > 0.0 && p < 1.0) || dof < 1) {
    throw std::invalid_argument(std::string(__FILE__) + ": chi2_quantile: need 0 < p < 1 and "
                                "dof >= 1, got p = " + std::to_string(p) +
                                ", dof = " + std::to_string(dof));
  }
  const double k = 0.5 * dof;
  double lo = 0.0;
  double hi = dof + 10.0 * std::sqrt(2.0 * dof) + 100.0;
  while (gamma_p(k, 0.5 * hi) < p) hi *= 2.0;
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (gamma_p(k, 0.5 * mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double chi2_95(int dof) {
  static const std::array<double, kTableSize> table = [] {
    std::array<double, kTableSize> t{};
    for (int d = 1; d < kTableSize; ++d) t[d] = chi2_quantile(0.95, d);
    return t;
  }();
  if (dof >= 1 && dof < kTableSize) return table[dof];
  return chi2_quantile(0.95, dof);
}

}  // namespace vid
