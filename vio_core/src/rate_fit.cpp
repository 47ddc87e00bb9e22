/// @file rate_fit.cpp
/// @brief Local quadratic fit of the gyro (rate_fit.h).
#include "vio_core/rate_fit.h"

#include <Eigen/Cholesky>
#include <cstdlib>

namespace vid {

std::optional<Eigen::Vector3d> fit_rate(const std::vector<GyroSample>& samples, TimeNs t_ns, TimeNs half_window_ns) {
  // Normal equations in the scaled time x = (t_i - t) / half_window (|x| <= 1): well
  // conditioned, and three unknowns need no more than a 3x3 solve.
  Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d AtY = Eigen::Matrix3d::Zero();  // row k: sum x^k * gyro^T
  int n = 0;
  for (const GyroSample& s : samples) {
    if (std::llabs(s.t_ns - t_ns) > half_window_ns) continue;
    const double x = static_cast<double>(s.t_ns - t_ns) / static_cast<double>(half_window_ns);
    const Eigen::Vector3d a(1.0, x, x * x);
    AtA += a * a.transpose();
    AtY += a * s.gyro_I.transpose();
    ++n;
  }
  if (n < 8) return std::nullopt;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(AtA);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
  const Eigen::Matrix3d c = ldlt.solve(AtY);
  return Eigen::Vector3d(c.row(0).transpose());
}

}  // namespace vid
