#pragma once
/// @file mono_alignment.h
/// @brief The in-flight initializer's math for one camera (dynamic_initializer.h;
/// docs/notes/initialization.md, docs/model.md eq. (45a)). One camera gives the frames' positions
/// only up to scale, so the visual and the inertial parts cannot be solved one after the other as
/// with stereo (inertial_alignment.h): the frame positions p_k, the landmarks, the gyro-bias
/// correction and (v_I, g_I, b_a) of the last frame are solved jointly, the accelerometer's double
/// integrals p_k = v_I tau_k + g_I tau_k^2 / 2 + alpha_k - C_k b_a giving the scale.
///   1. Start: (a) the structure up to scale from the bearings' homogeneous rows with the gyro's
///      rotations held (the null vector by inverse iteration, depth-weighted, outliers past 4 sigma
///      dropped), alternated with a gyro-bias step on the same rows; (b) the scale, v_I and g_I
///      (|g_I| fixed, the global minimum on the sphere) from the alphas, b_a held at 0.
///   2. Estimate: Levenberg-Marquardt on the bearings' reprojection errors plus the alphas'
///      accelerometer noise (the positions' residual p_k - v tau - g tau^2/2 - alpha_k - J_alpha
///      d_bg + C_k b_a, whitened by the twice-integrated white noise) and the b_a prior, with
///      |g_I| fixed (tangent-plane steps).
/// The covariance is the Gauss-Newton one at the solution, scaled by max(1, chi2 / dof). The scale
/// is seen only through the accelerometer; MonoAlignment::scale_sigma says how well, and the
/// initializer refuses a window whose scale is too uncertain for that linearization to hold.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "vio_core/inertial_alignment.h"

namespace vid::align {

/// @brief What the joint solve needs besides the tracks and the IMU's integrals.
struct MonoNoise {
  double sigma_norm = 0.0;     ///< bearing noise in normalized coordinates
  double accel_density = 0.0;  ///< [m/s^2/sqrt(Hz)], 3 axes alike
  double sigma_ba = 0.1;       ///< prior sigma of the accelerometer bias [m/s^2]
  double gravity = 9.81;       ///< |g| [m/s^2]
};

/// @brief The joint solution: the last frame's state and the frames' positions (FramePositions'
/// chi2_per_dof is the bearings' part; AlignedState's the whole cost's).
struct MonoAlignment {
  AlignedState state;
  FramePositions pos;
  double inertial_chi2_per_dof = 0.0;  ///< of the alphas' residuals alone
  /// Relative sigma of the scale: of the first frame's position (the window's translation) along
  /// itself, over its length.
  double scale_sigma = 0.0;
};

/// @brief Solve one mono window (cam0 bearings only; Track::obs[].cam must be 0).
/// @param w the window's integrals (integrate_window) at the current gyro bias
/// @param J_bg per frame, the right perturbation of R_Kk per unit gyro bias (empty: no bias solve)
/// @param J_alpha_bg d alpha_k / d b_g (3K x 3; empty with J_bg empty)
/// @param why says what failed
std::optional<MonoAlignment> solve_mono_window(const std::vector<Track>& tracks, const WindowIntegrals& w,
                                               const Eigen::Isometry3d& T_IC, const MonoNoise& noise,
                                               const std::vector<Eigen::Matrix3d>& J_bg,
                                               const Eigen::MatrixXd& J_alpha_bg, std::string* why);

}  // namespace vid::align
