#pragma once
/// @file metrics.h
/// @brief ATE (posyaw) and external-force RMSE of a run (summary.json, and the C++ tests). The
/// association and alignment follow vid_eval (evo's nearest-timestamp rule, closed-form
/// 4-DoF alignment) so the two agree on the same files.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "types/measurements.h"

namespace vid::system {

/// @brief A time series of 3-vectors.
struct Vec3Series {
  std::vector<TimeNs> t_ns;
  std::vector<Eigen::Vector3d> v;
};

/// @brief How a file writes its stamps: decimal seconds (TUM) or integer nanoseconds (ASL CSV).
enum class StampText { kSeconds, kNanoseconds };

/// @brief Index pairs (est, gt) by evo's rule, as vid-eval (eval/vid_eval/association.py) and
/// evo find them in the written files: walk the shorter series (the estimate on equal counts),
/// take the nearest sample of the other within max_diff_ns (ties to the earlier one), distances
/// compared in double seconds as evo reads each file (@p est_text, @p gt_text), so near ties
/// below a double's resolution at epoch times resolve as there.
std::vector<std::pair<std::size_t, std::size_t>> associate_nearest(const std::vector<TimeNs>& t_est,
                                                                   const std::vector<TimeNs>& t_gt,
                                                                   TimeNs max_diff_ns = 10'000'000,
                                                                   StampText est_text = StampText::kNanoseconds,
                                                                   StampText gt_text = StampText::kNanoseconds);

/// @brief Result of a trajectory comparison.
struct AteResult {
  double rmse_m = 0.0;
  std::size_t pairs = 0;
  double yaw_rad = 0.0;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

/// @brief ATE position RMSE after the closed-form yaw + translation alignment over all pairs.
std::optional<AteResult> ate_posyaw(const Vec3Series& est, const Vec3Series& gt);

/// @brief The estimate cut at @p starts (ascending; the times the estimator was initialized):
/// each piece is its own world frame after a re-initialization, so each is aligned on its own
/// (ate_posyaw); rmse_m pools their squared errors, yaw_rad is per piece. One piece when
/// @p starts has fewer than two entries.
struct SegmentedAte {
  AteResult pooled;                 ///< rmse over every pair, pairs the total (yaw: the first piece's)
  std::vector<TimeNs> t_start_ns;   ///< start of each aligned piece
  std::vector<AteResult> segments;  ///< per piece (pieces without a pair left out)
};
std::optional<SegmentedAte> ate_posyaw_segments(const Vec3Series& est, const Vec3Series& gt,
                                                const std::vector<TimeNs>& starts);

/// @brief The piece of @p s with t in [t0, t1).
Vec3Series slice(const Vec3Series& s, TimeNs t0, TimeNs t1);

/// @brief RMSE of ||f_est - f_gt|| [m/s^2] after nearest association; nullopt without pairs.
/// Both series must be in one frame: rotate a world-frame estimate into the ground truth's
/// world first (rotate_about_z with the ATE's yaw), the estimator's heading is its own.
std::optional<double> force_rmse(const Vec3Series& est, const Vec3Series& gt, std::size_t* pairs = nullptr);

/// @brief Every vector of a series rotated by yaw_rad about z (the world-frame gauge of an
/// estimate, as found by ate_posyaw).
Vec3Series rotate_about_z(const Vec3Series& s, double yaw_rad);

/// @brief Ground-truth world-frame vectors expressed in the body frame, R_WI^T f_W, with the
/// nearest ground-truth orientation (within 10 ms); samples without one are dropped.
Vec3Series world_to_body(const Vec3Series& f_W, const std::vector<TimeNs>& t_R,
                         const std::vector<Eigen::Matrix3d>& R_WI);

/// @brief Mass at time t from a mass series: linear interpolation, held outside its span.
double mass_at(const std::vector<TimeNs>& t_ns, const std::vector<double>& mass_kg, TimeNs t);

}  // namespace vid::system
