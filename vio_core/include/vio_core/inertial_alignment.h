#pragma once
/// @file inertial_alignment.h
/// @brief The math of the in-flight initializer (dynamic_initializer.h;
/// docs/notes/initialization.md, docs/model.md eqs. (43)-(45)): over a window of camera frames
/// k = 0..K, with all quantities in the IMU frame I_K of the last frame,
///   1. gyro-integrated rotations R_Kk and the accelerometer's double integrals
///      alpha_k = int_{t_K}^{t_k} (t_k - u) R_K(u) a(u) du (integrate_window);
///   2. the frame positions p_k (p_K = 0) and landmarks from the stereo bearings with the
///      rotations held (linear least squares refined on the reprojection errors; the scale
///      comes from the stereo baseline: solve_frame_positions);
///   3. velocity v_K, gravity g_K (|g| fixed) and accelerometer bias from
///      p_k = v_K tau_k + g_K tau_k^2 / 2 + alpha_k - C_k b_a, tau_k = t_k - t_K, a generalized
///      least squares whose noise is the visual positions' covariance plus the accelerometer
///      white noise integrated twice (solve_gravity_velocity).
/// As VINS-Mono's visual-inertial alignment and OpenVINS's dynamic initializer, but with stereo
/// depth the scale is known and the system stays linear.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "types/calibration.h"
#include "types/measurements.h"

namespace vid::align {

/// @brief One IMU sample of the window (bias not removed).
struct ImuRow {
  TimeNs t = 0;
  Eigen::Vector3d gyro, accel;
};

/// @brief What the IMU says between the window's frames, in I_K (index k: frame k).
struct WindowIntegrals {
  std::vector<double> tau;             ///< t_k - t_K [s] (<= 0)
  std::vector<Eigen::Matrix3d> R_Kk;   ///< rotation I_k -> I_K (gyro, bias 0)
  std::vector<Eigen::Vector3d> alpha;  ///< int (t_k - u) R_K(u) a(u) du from t_K
  std::vector<Eigen::Matrix3d> C;      ///< d alpha_k / d(-b_a): the same integral of R_K(u)
};

/// @brief Integrate the samples (trapezoid, midpoint rotation; inputs interpolated at the
/// frame times). Frame times must be increasing and inside the samples' span.
WindowIntegrals integrate_window(const std::vector<ImuRow>& imu, const std::vector<TimeNs>& frame_times);

/// @brief One cam0/cam1 bearing of a landmark in frame k.
struct Bearing {
  int frame = 0;
  int cam = 0;  ///< index into the cameras
  Eigen::Vector2d xy;  ///< undistorted normalized coordinates
};
/// @brief All bearings of one landmark in the window.
struct Track {
  std::uint64_t id = 0;
  std::vector<Bearing> obs;
};

/// @brief Frame positions in I_K with their covariance.
struct FramePositions {
  std::vector<Eigen::Vector3d> p;  ///< p_k in I_K (p_K = 0)
  Eigen::MatrixXd cov;             ///< 3K x 3K over frames 0..K-1
  double chi2_per_dof = 0.0;       ///< of the weighted bearing residuals (1 when the noise fits)
  Eigen::Vector3d d_bg = Eigen::Vector3d::Zero();  ///< gyro-bias correction (with J_bg)
  Eigen::Matrix3d cov_bg = Eigen::Matrix3d::Zero();
  int landmarks = 0;
  int observations = 0;
};

/// @brief Least squares over the landmarks and frame positions with the rotations R_Kk held;
/// each bearing gives two rows (x_C - x z_C, y_C - y z_C) weighted by 1 / (sigma_norm z_C),
/// twice (depths from the first pass), dropping bearings beyond 4 sigma; from that start,
/// Levenberg-Marquardt on the reprojection errors (the linear system's algebraic error reads
/// the positions 3-15 % short at low disparity). The covariance, the Gauss-Newton one at the
/// solution, is scaled by max(1, chi2 / dof). @p why says what failed. With @p J_bg (per frame, the right
/// perturbation of R_Kk per unit gyro bias: R_Kk(b + d) = R_Kk Exp(J_k d)) the gyro-bias
/// correction d is solved along (linearized about the previous pass's landmarks).
std::optional<FramePositions> solve_frame_positions(const std::vector<Track>& tracks,
                                                    const std::vector<Eigen::Matrix3d>& R_Kk,
                                                    const std::vector<Eigen::Isometry3d>& T_IC, double sigma_norm,
                                                    std::string* why, const std::vector<Eigen::Matrix3d>& J_bg = {});

namespace detail {
/// @brief Reprojection cost (in units of sigma_norm) of the kept bearings at
/// x = (p_0..p_{K-1}, L_j, d_bg) and, with @p H and @p g, its Gauss-Newton normal equations
/// (H = J^T J, g = J^T r); +inf when a kept point is behind its camera. The refinement inside
/// solve_frame_positions; declared here for its numeric-derivative test.
double reprojection_system(const std::vector<Track>& tracks, const std::vector<Eigen::Matrix3d>& R_Kk,
                           const std::vector<Eigen::Isometry3d>& T_IC, double sigma_norm,
                           const std::vector<Eigen::Matrix3d>& J_bg, const std::vector<std::vector<bool>>& keep,
                           const Eigen::VectorXd& x, Eigen::MatrixXd* H, Eigen::VectorXd* g);
}  // namespace detail

/// @brief The state of the last frame.
struct AlignedState {
  Eigen::Vector3d v_I;  ///< velocity in I_K
  Eigen::Vector3d g_I;  ///< gravity in I_K (|g_I| = gravity)
  Eigen::Vector3d b_a;
  Eigen::Matrix<double, 9, 9> cov;  ///< of (v_I, g_I, b_a); g_I's along itself is 0
  double chi2_per_dof = 0.0;        ///< of the position fit (scaled into cov when > 1)
};

/// @brief Generalized least squares for (v_I, g_I, b_a) with |g_I| = gravity (Gauss-Newton on
/// the tangent plane) and the prior b_a ~ N(0, sigma_ba^2); accel_density [m/s^2/sqrt(Hz)] sets
/// the covariance of the alphas (3 axes alike); @p alpha_cov_extra (3K x 3K, optional) adds
/// what else the alphas are uncertain by (the gyro bias's error turning them).
AlignedState solve_gravity_velocity(const FramePositions& pos, const WindowIntegrals& w, double accel_density,
                                    double sigma_ba, double gravity,
                                    const Eigen::MatrixXd& alpha_cov_extra = Eigen::MatrixXd());

/// @brief Two unit vectors spanning the plane orthogonal to the unit direction @p d (the
/// tangent plane of |g| fixed: g = gravity (d + B delta)).
Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& d);
/// @brief d (v, g, b_a) / d (v, delta, b_a) about d (9 x 8): how a tangent-plane covariance maps
/// to the (v_I, g_I, b_a) one.
Eigen::Matrix<double, 9, 8> tangent_map(const Eigen::Vector3d& d, double gravity);

/// @brief Covariance between alpha_i and alpha_k per axis for unit white noise density:
/// int_{max(tau_i, tau_k)}^0 (u - tau_i)(u - tau_k) du.
double alpha_covariance(double tau_i, double tau_k);

}  // namespace vid::align
