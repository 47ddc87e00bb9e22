#pragma once
/// @file run_metrics.h
/// @brief ATE (posyaw) and external-force RMSE computed by vid_run for summary.json. The
/// association and alignment follow vid_eval (evo's nearest-timestamp rule, closed-form
/// 4-DoF alignment) so the two agree on the same files.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "vio_core/measurements.h"

namespace vid::runner {

/// @brief A time series of 3-vectors.
struct Vec3Series {
  std::vector<TimeNs> t_ns;
  std::vector<Eigen::Vector3d> v;
};

/// @brief Index pairs (est, gt) by evo's rule: walk the shorter series, take the nearest
/// sample of the other within max_diff_ns (ties to the earlier one).
std::vector<std::pair<std::size_t, std::size_t>> associate_nearest(const std::vector<TimeNs>& t_est,
                                                                   const std::vector<TimeNs>& t_gt,
                                                                   TimeNs max_diff_ns = 10'000'000);

/// @brief Result of a trajectory comparison.
struct AteResult {
  double rmse_m = 0.0;
  std::size_t pairs = 0;
  double yaw_rad = 0.0;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

/// @brief ATE position RMSE after the closed-form yaw + translation alignment over all pairs.
std::optional<AteResult> ate_posyaw(const Vec3Series& est, const Vec3Series& gt);

/// @brief RMSE of ||f_est - f_gt|| [m/s^2] after nearest association; nullopt without pairs.
std::optional<double> force_rmse(const Vec3Series& est_W, const Vec3Series& gt_W, std::size_t* pairs = nullptr);

/// @brief Mass at time t from a mass series: linear interpolation, held outside its span.
double mass_at(const std::vector<TimeNs>& t_ns, const std::vector<double>& mass_kg, TimeNs t);

}  // namespace vid::runner
