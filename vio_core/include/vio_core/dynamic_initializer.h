#pragma once
/// @file dynamic_initializer.h
/// @brief In-flight initialization from a short window of camera frames and IMU samples
/// (docs/notes/initialization.md, init_mode auto): gravity direction, velocity, accelerometer and
/// gyro bias of the last frame, with their covariance, from inertial_alignment.h (a stereo
/// pair: init_dynamic_window_s) or mono_alignment.h (one camera: init_dynamic_window_mono_s);
/// position and yaw the gauge as in the static initializer, in dynamics mode the
/// external force from the last 0.1 s of a - b_a - T/m.

#include <Eigen/Core>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "types/calibration.h"
#include "types/measurements.h"
#include "vio_core/estimator_params.h"
#include "vio_core/inertial_alignment.h"
#include "vio_core/initializer.h"

namespace vid {

/// @brief What the last attempt found (for tests and the benchmark).
struct DynamicInitDiagnostics {
  int frames = 0, landmarks = 0, observations = 0;
  double visual_chi2_per_dof = 0.0, inertial_chi2_per_dof = 0.0;
  double scale_sigma = 0.0;  ///< mono: relative sigma of the window's translation (its scale)
};

/// @brief Sliding window of IMU samples and camera frames; tries an alignment at every frame
/// once the window spans its length.
class DynamicInitializer {
 public:
  /// @param cameras sorted by cam_id: one camera (mono), or the first two are the stereo pair.
  DynamicInitializer(const EstimatorParams& params, std::vector<CameraCalib> cameras);
  /// @brief One IMU sample (time-ordered) with its thrust (ignored in imu mode).
  void add_imu(TimeNs t_ns, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, const Eigen::Vector3d& T_m);
  /// @brief One frame, its time on the IMU clock and no later than the last IMU sample.
  /// Returns the state at the frame's time once the window aligns.
  std::optional<InitResult> add_frame(const FeatureFrame& frame);
  /// @brief Why the last full window was rejected ("" if none yet).
  const std::string& last_rejection() const { return reason_; }
  const DynamicInitDiagnostics& diagnostics() const { return diag_; }
  /// @brief Median rotation-compensated parallax of cam0 [px] between the first frame at or
  /// after @p t_from (within 0.1 s) and the newest frame; nullopt without such frames or with
  /// fewer than 10 features seen in both. An IMU cannot tell hovering from cruising at constant
  /// velocity; this can.
  std::optional<double> parallax_px(TimeNs t_from) const;
  /// @brief Forget everything (re-initialization).
  void reset();

 private:
  struct ImuSample3 {
    TimeNs t;
    Eigen::Vector3d w, a, T;
  };
  std::optional<InitResult> try_window();
  bool mono() const { return cameras_.size() == 1; }
  double window_s() const { return mono() ? params_.init_dynamic_window_mono_s : params_.init_dynamic_window_s; }
  /// The window's integrals at the frame times with the gyro bias b_g removed.
  align::WindowIntegrals integrate(const std::vector<TimeNs>& times, const Eigen::Vector3d& b_g) const;
  /// d alpha_k / d b_g (3K x 3) of the window at b_g, numerically.
  Eigen::MatrixXd alpha_bias_jacobian(const std::vector<TimeNs>& times, const Eigen::Vector3d& b_g,
                                      const align::WindowIntegrals& w) const;
  /// Per frame, the right perturbation of R_Kk per unit gyro bias at b_g, numerically.
  std::vector<Eigen::Matrix3d> rotation_bias_jacobians(const std::vector<TimeNs>& times, const Eigen::Vector3d& b_g,
                                                       const align::WindowIntegrals& w) const;
  /// The mono branch of try_window: the joint solve, re-integrated until the gyro bias settles.
  std::optional<InitResult> align_mono(const std::vector<align::Track>& tracks, const std::vector<TimeNs>& times,
                                       double sigma_norm);
  /// The window's camera poses in the world of @p r (the trajectory across a re-initialization).
  void add_window_poses(InitResult* r, const std::vector<TimeNs>& times, const align::WindowIntegrals& w,
                        const std::vector<Eigen::Vector3d>& p) const;
  std::vector<align::Track> window_tracks(std::vector<int>* per_frame) const;
  InitResult hand_over(const align::AlignedState& s) const;

  EstimatorParams params_;
  std::vector<CameraCalib> cameras_;
  std::deque<ImuSample3> imu_;
  std::deque<FeatureFrame> frames_;
  std::string reason_;
  DynamicInitDiagnostics diag_;
  Eigen::Vector3d b_g_ = Eigen::Vector3d::Zero();  ///< of the last window
  Eigen::Matrix3d cov_b_g_ = Eigen::Matrix3d::Zero();
};

}  // namespace vid
