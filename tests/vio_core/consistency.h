#pragma once
// Helpers shared by the consistency (NEES) tests on synthetic and simulator data.
#include <Eigen/Cholesky>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <utility>
#include <vector>

#include "geometry/so3.h"
#include "vio_core/state.h"

namespace vid::test {

/// Two-sided 95% band of the mean of `runs` chi2(3) samples: chi2(3 runs) quantiles / runs
/// (Wilson-Hilferty, < 0.5% error at these dof).
inline std::pair<double, double> nees_band(int runs) {
  const double k = 3.0 * runs;
  auto q = [k](double z) {
    const double a = 2.0 / (9.0 * k);
    const double c = 1.0 - a + z * std::sqrt(a);
    return k * c * c * c;
  };
  return {q(-1.959963984540054) / runs, q(1.959963984540054) / runs};
}

/// Write run-averaged NEES curves as the CSV that `vid-eval nees` reads and plots
/// (eval/vid_eval/core/formats.py NEES_COLUMNS: the header first, then the run count and band).
inline void write_nees_csv(const std::filesystem::path& path, int runs, const std::vector<double>& t,
                           const std::vector<double>& theta, const std::vector<double>& p,
                           const std::vector<double>& F, std::size_t stride = 1) {
  const auto [lo, hi] = nees_band(runs);
  std::filesystem::create_directories(path.parent_path());
  std::ofstream csv(path);
  csv << "#t [s],nees_theta [],nees_p [],nees_F []\n";
  csv << "# runs=" << runs << " band_lo=" << lo << " band_hi=" << hi << "\n";
  csv << std::setprecision(10);  // times stay distinct (the reader wants them increasing)
  for (std::size_t i = 0; i < t.size(); i += stride)
    csv << t[i] << "," << theta[i] << "," << p[i] << "," << F[i] << "\n";
}

/// Perturb x by one draw from N(0, P) (error-state layout of the IMU block, any of 15 / 18 /
/// 21 dims), so that an initial estimate is honestly distributed around the truth.
inline void perturb_by_covariance(ImuState& x, const Eigen::MatrixXd& P, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  Eigen::VectorXd z(P.rows());
  for (int i = 0; i < z.size(); ++i) z(i) = nd(rng);
  const Eigen::VectorXd dx = Eigen::MatrixXd(P.llt().matrixL()) * z;
  x.T_WI.q = so3::boxplus(x.T_WI.q, dx.segment<3>(imu_idx::kTheta));
  x.T_WI.p += dx.segment<3>(imu_idx::kP);
  x.v_WI += dx.segment<3>(imu_idx::kV);
  x.b_g += dx.segment<3>(imu_idx::kBg);
  x.b_a += dx.segment<3>(imu_idx::kBa);
  if (P.rows() >= 18) x.F_ext += dx.segment<3>(imu_idx::kF);
  if (P.rows() >= 21) x.F_dot += dx.segment<3>(imu_idx::kFdot);
}

}  // namespace vid::test
