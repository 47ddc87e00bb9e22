#pragma once
/// @file msckf_types.h
/// @brief Plain data shared by the MSCKF visual update and the estimator core: clone poses,
/// camera extrinsics, feature tracks and the update parameters. Eigen only.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "types/measurements.h"

namespace vid::msckf {

/// @brief One stochastic clone of the IMU pose at a camera time.
///
/// Error block in P (6 columns starting at cov_index): [dtheta(3), dp(3)], with the
/// orientation error a right perturbation R_WI = R_WI_hat * Exp(dtheta) and p_WI = p_hat + dp
/// (docs/design.md §3). Jacobians are evaluated at the first estimates (*_fej); residuals use the
/// current values.
struct ClonePose {
  TimeNs t_ns = 0;
  Eigen::Matrix3d R_WI = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R_WI_fej = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_WI_fej = Eigen::Vector3d::Zero();
  int cov_index = -1;  ///< first column of [dtheta, dp] in P
};

/// @brief Pose of camera cam_id (index in the extrinsics vector) in the IMU frame.
///
/// When cov_index >= 0 the extrinsics are estimated: error block [dtheta_IC(3), dp_IC(3)] with
/// R_IC = R_IC_hat * Exp(dtheta_IC) and p_IC = p_IC_hat + dp_IC (p_IC in I).
struct CameraExtrinsic {
  Eigen::Isometry3d T_IC = Eigen::Isometry3d::Identity();
  int cov_index = -1;  ///< -1: not estimated
};

/// @brief One observation of a feature: undistorted normalized coordinates (x/z, y/z).
struct TrackObservation {
  TimeNs t_ns = 0;
  int cam_id = 0;
  Eigen::Vector2d uv_norm = Eigen::Vector2d::Zero();
};

/// @brief All observations of one feature, sorted by (t_ns, cam_id).
struct FeatureTrack {
  std::uint64_t feature_id = 0;
  std::vector<TrackObservation> obs;
};

/// @brief Triangulation settings (linear midpoint + Gauss-Newton in inverse depth).
struct TriangulationParams {
  double min_depth = 0.1;        ///< [m] in the anchor camera and every observing camera
  double max_depth = 60.0;       ///< [m] in the anchor camera
  int gn_iterations = 10;        ///< max Gauss-Newton iterations
  double gn_tolerance = 1e-10;   ///< stop when the inverse-depth step norm is below this
  double min_parallax_rad = 0.0; ///< reject if the largest angle between rays is smaller
  double min_baseline = 0.0;     ///< [m] reject if camera centres span less than this
  double max_condition = 1e4;    ///< reject if cond(linear system) is larger
  double max_reproj_error_norm = 0.05;  ///< per observation, normalized units, after GN
};

/// @brief How the stacked per-feature systems are compressed to at most (touched columns)
/// rows. Both keep H^T H and H^T r, i.e. give the same EKF update.
enum class Compression {
  kQr,               ///< Householder QR of the stacked nullspace-projected rows (default)
  kNormalEquations,  ///< H^T H, H^T r accumulated from the block structure, pivoted LDLT
};

/// @brief Parameters of the visual MSCKF update.
struct VisualUpdateParams {
  double sigma_norm = 1.0 / 400.0;  ///< pixel noise in normalized image units (1 px / f)
  double chi2_multiplier = 1.0;     ///< gate: chi2 <= multiplier * chi2inv(0.95, dof)
  int min_observations = 3;         ///< observations at clone times (stereo pair = 2)
  Compression compression = Compression::kQr;
  TriangulationParams triangulation;
};

}  // namespace vid::msckf
