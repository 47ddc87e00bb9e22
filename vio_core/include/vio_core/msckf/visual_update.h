#pragma once
/// @file visual_update.h
/// @brief The MSCKF visual update: from feature tracks and the clone window to one stacked,
/// nullspace-projected, chi2-gated and QR-compressed linear system for a single EKF update.

#include <Eigen/Core>
#include <vector>

#include "vio_core/msckf/msckf_types.h"

namespace vid::msckf {

/// @brief Linear measurement system r = H dx + n, n ~ N(0, noise_var * I).
///
/// H has P.cols() columns (only clone / estimated-extrinsic columns are non-zero).
/// H may have zero rows (nothing to update).
struct VisualLinearSystem {
  Eigen::MatrixXd H;
  Eigen::VectorXd r;
  double noise_var = 0.0;
  int features_used = 0;
  int features_rejected_chi2 = 0;
  double chi2_sum = 0.0;  ///< chi2 of the features used (noise fit: chi2_sum / dof_sum ~ 1)
  long dof_sum = 0;       ///< their degrees of freedom
  int features_rejected_triangulation = 0;
  /// Tracks with fewer than min_observations observations at clone times (not an error).
  int features_too_short = 0;
};

/// @brief Build the visual update for the given tracks.
///
/// Per feature: triangulate with the current clone values, linearize at the first estimates
/// (FEJ) of the clones, project onto the left nullspace of the feature Jacobian, chi2-gate at
/// 95% (times params.chi2_multiplier) with S = H P H^T + sigma^2 I using only the clone /
/// extrinsic blocks of P; then stack all features and QR-compress when there are more rows
/// than touched columns. Observations at times that are not clone times are ignored.
///
/// Throws std::invalid_argument if a track references a cam_id with no extrinsic, or if a
/// cov_index does not fit P.
VisualLinearSystem build_visual_update(const std::vector<FeatureTrack>& tracks,
                                       const std::vector<ClonePose>& clones,
                                       const std::vector<CameraExtrinsic>& extrinsics,
                                       const Eigen::MatrixXd& P,
                                       const VisualUpdateParams& params);

}  // namespace vid::msckf
