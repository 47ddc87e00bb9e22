#pragma once
/// @file state.h
/// @brief Filter state and covariance bookkeeping: typed variables that know their column in
/// the error-state covariance P (IMU block, optional time offset, stochastic clones, force clones),
/// clone augmentation, marginalization, error-state correction, and health checks.
///
/// Error-state layout of the IMU block (right perturbation on orientation, docs/design.md §3):
/// [dtheta(3), dp_WI(3), dv_WI(3), db_g(3), db_a(3)] and, in dynamics mode, dF_ext(3) (in the
/// state's force frame, EstimatorParams::force_frame), then optionally dF_ext/dt(3) in the same
/// frame (EstimatorParams::force_rate_random_walk > 0), then optionally the thrust scale ds(1)
/// (EstimatorParams::thrust_scale_random_walk > 0; ImuLayout says where each sits).
/// The time offset t_d (when estimated) follows the IMU block; pose clones and force clones (each oldest
/// first, interleaved in the order they were taken) follow those.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.h"
#include "types/measurements.h"
#include "vio_core/estimator_params.h"

namespace vid {

/// @brief Column offsets inside the IMU error block.
namespace imu_idx {
constexpr int kTheta = 0;
constexpr int kP = 3;
constexpr int kV = 6;
constexpr int kBg = 9;
constexpr int kBa = 12;
constexpr int kF = 15;  ///< only in dynamics mode
constexpr int kFdot = 18;  ///< only with the force-rate state
}  // namespace imu_idx

/// @brief Which optional states the IMU error block carries, its size, and the size of the
/// propagation noise vector [n_g, n_a, w_g, w_a, (w_F), (w_Fd), (w_s)].
struct ImuLayout {
  bool force = false;         ///< F_ext (dynamics mode)
  bool force_rate = false;    ///< dF_ext/dt (needs force)
  bool thrust_scale = false;  ///< s (needs force)

  /// @brief The layout the estimator settings ask for (the one place this is decided).
  static ImuLayout from(const EstimatorParams& p);
  int dim() const { return 15 + (force ? 3 : 0) + (force_rate ? 3 : 0) + (thrust_scale ? 1 : 0); }
  int noise_dim() const { return dim() - 3; }  ///< one noise per state except theta, p, v; + n_g, n_a
  /// @brief Column of ds (valid with thrust_scale).
  int thrust_scale_index() const { return imu_idx::kF + 3 + (force_rate ? 3 : 0); }
};

/// @brief Mean of the IMU block.
struct ImuState {
  Pose T_WI;  ///< IMU pose in the world
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();
  /// Mass-normalized external force [m/s^2] in the state's force frame (I or W); use
  /// force_in_body() / force_in_world() to read it in a given frame.
  Eigen::Vector3d F_ext = Eigen::Vector3d::Zero();
  /// dF_ext/dt [m/s^3] in the same frame; zero unless the force-rate state is on.
  Eigen::Vector3d F_dot = Eigen::Vector3d::Zero();
  /// Thrust scale s: the thrust acceleration is s T_m (T_m from the rotor speeds with the
  /// calibrated coefficients and mass, so s = m0 / m for a payload change); 1 unless the
  /// thrust-scale state is on.
  double thrust_scale = 1.0;
};

/// @brief Mass-normalized linear body drag at x: -diag(D) R_WI^T v_WI, in I [m/s^2].
Eigen::Vector3d drag_in_body(const ImuState& x, const Eigen::Vector3d& D);

/// @brief F_ext of x in the body frame I (F_I = R_WI^T F_W in the world-frame model).
Eigen::Vector3d force_in_body(const ImuState& x, ForceFrame frame);
/// @brief F_ext of x in the world frame W (F_W = R_WI F_I in the body-frame model).
Eigen::Vector3d force_in_world(const ImuState& x, ForceFrame frame);
/// @brief Store a force given in I into x.F_ext in the model's frame.
void set_force_from_body(ImuState& x, ForceFrame frame, const Eigen::Vector3d& F_I);

/// @brief First estimates of the IMU pose/velocity (the value the state had when it was first
/// propagated to the current time; used for observability-consistent linearization).
struct ImuFej {
  Pose T_WI;
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
};

/// @brief Stochastic clone of the IMU pose at a camera time (msckf::ClonePose is its
/// rotation-matrix form for the visual update).
struct CloneState {
  TimeNs t_ns = 0;
  Pose T_WI;      ///< current estimate
  Pose T_WI_fej;  ///< first estimate (the IMU's when the clone was taken)
  int cov_index = -1;  ///< column of [dtheta, dp] in P
};

/// @brief Stochastic clone of F_ext at a camera time (fixed-lag smoothing,
/// docs/notes/smoothing.md): later updates correct it through its cross-covariance, so while it
/// is kept it is the smoothed estimate of the force at its time.
struct ForceClone {
  TimeNs t_ns = 0;
  Eigen::Vector3d F_ext = Eigen::Vector3d::Zero();  ///< in the state's force frame [m/s^2]
  int cov_index = -1;  ///< column of dF_ext in P
};

/// @brief The camera-IMU time offset t_d (t_imu = t_cam + t_d), estimated in the filter.
struct TimeOffsetState {
  double t_d_s = 0.0;  ///< [s]
  int cov_index = -1;  ///< its column in P
};

/// @brief Result of a covariance health check.
struct CovarianceHealth {
  bool finite = true;
  bool positive_definite = true;  ///< positive semidefinite up to round-off, positive diagonal
  double max_asymmetry = 0.0;  ///< max |P - P^T| before symmetrization
};

/// @brief How a frame's true time relates to its clone's (docs/notes/time-offset.md).
struct CloneTiming {
  Eigen::Vector3d w_I = Eigen::Vector3d::Zero();   ///< body rate at the clone's time (Estimator::rate_for_clone)
  Eigen::Vector3d v_td_W = Eigen::Vector3d::Zero();  ///< world velocity in the t_d coupling
  double jitter_s = 0.0;  ///< 1-sigma timestamp noise of this frame, independent per frame
};

/// @brief IMU block + time offset + clones with one joint covariance. The camera extrinsics are
/// fixed (the calibration's); only t_d of the calibration can be estimated.
class FilterState {
 public:
  /// @brief The layout the estimator settings ask for: F_ext in dynamics mode, in
  /// params.force_frame, with dF_ext/dt when params.force_rate_random_walk > 0 (the defaults
  /// are EstimatorParams', written once there).
  explicit FilterState(const EstimatorParams& params);
  /// @brief An explicit layout (tests, benchmarks).
  /// @param with_force true in dynamics mode (adds F_ext to the IMU block).
  /// @param force_frame frame of the F_ext state
  /// @param with_force_rate adds dF_ext/dt after F_ext (needs with_force)
  /// @param with_thrust_scale adds the thrust scale s last (needs with_force)
  FilterState(bool with_force, ForceFrame force_frame, bool with_force_rate, bool with_thrust_scale = false);

  /// @brief Reset to one IMU block with the given mean and covariance (no clones, no time offset).
  void initialize(TimeNs t_ns, const ImuState& imu, const Eigen::MatrixXd& P_imu);

  bool with_force() const { return layout_.force; }
  ForceFrame force_frame() const { return force_frame_; }
  bool with_force_rate() const { return layout_.force_rate; }
  bool with_thrust_scale() const { return layout_.thrust_scale; }
  /// @brief Mass-normalized linear body drag of the dynamics model, F_drag_I = -diag(D) v_I
  /// [1/s] (docs/design.md §3 "Rotor drag"); a known model constant, not a state. Zero (the
  /// default) leaves the model as it was.
  void set_linear_drag(const Eigen::Vector3d& D) { linear_drag_ = D; }
  const Eigen::Vector3d& linear_drag() const { return linear_drag_; }
  bool with_drag() const { return layout_.force && !linear_drag_.isZero(0.0); }
  const ImuLayout& layout() const { return layout_; }
  int imu_dim() const { return layout_.dim(); }
  int dim() const { return static_cast<int>(P_.rows()); }
  TimeNs time() const { return t_ns_; }
  void set_time(TimeNs t) { t_ns_ = t; }

  ImuState& imu() { return imu_; }
  const ImuState& imu() const { return imu_; }
  ImuFej& imu_fej() { return imu_fej_; }
  const ImuFej& imu_fej() const { return imu_fej_; }
  /// @brief Set the IMU first estimates to the current mean (FEJ off, or after init).
  void reset_imu_fej();

  const std::deque<CloneState>& clones() const { return clones_; }
  const std::deque<ForceClone>& force_clones() const { return force_clones_; }

  Eigen::MatrixXd& P() { return P_; }
  const Eigen::MatrixXd& P() const { return P_; }

  /// @brief Add a clone of the current IMU pose at the current time: P grows by 6 with the
  /// clone fully correlated to the IMU pose. The clone's first estimate is the IMU's.
  /// With the time-offset state, the current time is the image's estimated IMU-clock time
  /// t_cam + t_d_hat, and the clone is the pose at the true one: its error is the IMU pose's
  /// plus [w_I; v_td_W] times the offset's error (the caller passes the rates it trusts; the
  /// estimator's choice is in Estimator::process_frame). A timestamp jitter adds the pose change
  /// over it, [w_I; v_WI] jitter_s, as independent noise of the clone.
  void augment_clone(const CloneTiming& timing = CloneTiming());
  /// @brief Remove the oldest clone (marginalize: drop its rows/cols). No-op without clones.
  void marginalize_oldest_clone();

  /// @brief Add a clone of the current F_ext at the current time: P grows by 3 with the clone
  /// fully correlated to F_ext (docs/model.md eq. (35)). Needs the force state (throws std::logic_error).
  void augment_force_clone();
  /// @brief Remove the oldest force clone (marginalize: drop its rows/cols). No-op without one.
  void marginalize_oldest_force_clone();

  /// @brief Add the time-offset variable t_d with standard deviation @p sigma_s, right after the
  /// IMU block (indices of later variables shift).
  void add_time_offset(double t_d_s, double sigma_s);
  const std::optional<TimeOffsetState>& time_offset() const { return time_offset_; }
  /// @brief t_d: the estimate with the state, else @p fixed_s (the calibration's).
  double time_offset_or(double fixed_s) const { return time_offset_ ? time_offset_->t_d_s : fixed_s; }
  /// @brief 1-sigma of t_d (0 without the state).
  double time_offset_sigma() const;

  /// @brief Apply an error-state correction dx (size dim()): boxplus on rotations, + elsewhere.
  void apply_correction(const Eigen::VectorXd& dx);

  /// @brief Symmetrize P in place and report finiteness / positive (semi)definiteness (LDLT,
  /// O(n^3)).
  CovarianceHealth check_and_symmetrize();

 private:
  /// Drop rows/cols [at, at + k) of P (covariance::remove) and shift the indices of every
  /// variable behind them.
  void remove_block(int at, int k);

  ForceFrame force_frame_;
  ImuLayout layout_;
  Eigen::Vector3d linear_drag_ = Eigen::Vector3d::Zero();
  TimeNs t_ns_ = 0;
  ImuState imu_;
  ImuFej imu_fej_;
  std::optional<TimeOffsetState> time_offset_;
  std::deque<CloneState> clones_;
  std::deque<ForceClone> force_clones_;
  Eigen::MatrixXd P_;
};

}  // namespace vid
