/// @file rate_fit.cpp
/// @brief Local quadratic fit of the gyro (rate_fit.h).
#include "vio_core/rate_fit.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdlib>

#include "types/median.h"

namespace vid {

namespace {

/// Coefficients (rows: 1, x, x^2) of the quadratic fit and the per-axis residual variance.
struct Quadratic {
  Eigen::Matrix3d coeffs;
  Eigen::Vector3d residual_var;
};

std::optional<Quadratic> fit_quadratic(const std::vector<GyroSample>& samples, TimeNs t_ns, TimeNs half_window_ns) {
  // Normal equations in the scaled time x = (t_i - t) / half_window (|x| <= 1): well
  // conditioned, and three unknowns need no more than a 3x3 solve.
  Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d AtY = Eigen::Matrix3d::Zero();  // row k: sum x^k * gyro^T
  int n = 0;
  const auto scaled = [&](TimeNs t) { return static_cast<double>(t - t_ns) / static_cast<double>(half_window_ns); };
  for (const GyroSample& s : samples) {
    if (std::llabs(s.t_ns - t_ns) > half_window_ns) continue;
    const double x = scaled(s.t_ns);
    const Eigen::Vector3d a(1.0, x, x * x);
    AtA += a * a.transpose();
    AtY += a * s.gyro_I.transpose();
    ++n;
  }
  if (n < 8) return std::nullopt;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(AtA);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
  Quadratic q{ldlt.solve(AtY), Eigen::Vector3d::Zero()};
  for (const GyroSample& s : samples) {
    if (std::llabs(s.t_ns - t_ns) > half_window_ns) continue;
    const double x = scaled(s.t_ns);
    const Eigen::Vector3d model = q.coeffs.transpose() * Eigen::Vector3d(1.0, x, x * x);
    q.residual_var += (s.gyro_I - model).cwiseAbs2();
  }
  q.residual_var /= static_cast<double>(n - 3);
  return q;
}

/// Per-axis white-noise variance from the successive differences within the window:
/// (1.4826 MAD)^2 / 2, robust to the few differences an impact makes large.
Eigen::Vector3d noise_variance(const std::vector<GyroSample>& samples, TimeNs t_ns, TimeNs half_window_ns) {
  std::vector<double> d[3];
  const GyroSample* prev = nullptr;
  for (const GyroSample& s : samples) {
    if (std::llabs(s.t_ns - t_ns) > half_window_ns) continue;
    if (prev)
      for (int k = 0; k < 3; ++k) d[k].push_back(s.gyro_I[k] - prev->gyro_I[k]);
    prev = &s;
  }
  Eigen::Vector3d var = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (d[k].empty()) continue;
    const double m = upper_median(d[k]);
    for (double& x : d[k]) x = std::abs(x - m);
    const double sigma_diff = 1.4826 * upper_median(d[k]);
    var[k] = 0.5 * sigma_diff * sigma_diff;
  }
  return var;
}

}  // namespace

std::optional<AdaptiveRate> fit_rate_adaptive(const std::vector<GyroSample>& samples, TimeNs t_ns,
                                              TimeNs max_half_window_ns, TimeNs min_half_window_ns) {
  // Samples in time order (the caller's deque is); the successive differences need it.
  const Eigen::Vector3d noise_var = noise_variance(samples, t_ns, max_half_window_ns);
  std::optional<AdaptiveRate> shortest;
  for (TimeNs h = max_half_window_ns; h >= min_half_window_ns; h /= 2) {
    const std::optional<Quadratic> q = fit_quadratic(samples, t_ns, h);
    if (!q) break;
    shortest = AdaptiveRate{q->coeffs.row(0).transpose(), h, false};
    if ((q->residual_var.array() <= kRateFitResidualRatio * noise_var.array()).all()) {
      shortest->passed = true;
      break;
    }
  }
  return shortest;
}

}  // namespace vid
