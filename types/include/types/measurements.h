#pragma once
/// @file measurements.h
/// @brief Typed, time-stamped measurements shared by every source (dataset folders,
/// simulator, LCM) and every consumer (frontend, estimator, tools). Eigen only.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "geometry/pose.h"
#include "types/time.h"

namespace vid {

/// @brief A pose at a time: one row of a trajectory (trajectory_tum.txt, docs/formats.md §2).
struct TimedPose {
  TimeNs t_ns = 0;
  Pose T;  ///< the frames are those of the trajectory (T_WI for the estimator's)
};

/// @brief One IMU sample: body rate and specific force, both in the IMU frame I.
struct ImuSample {
  TimeNs t_ns = 0;
  Eigen::Vector3d gyro_I = Eigen::Vector3d::Zero();   ///< w_m [rad/s]
  Eigen::Vector3d accel_I = Eigen::Vector3d::Zero();  ///< a_m [m/s^2]
};

/// @brief Rotor speeds, in the unit declared by rotor0/sensor.yaml (rpm or rad/s).
struct RotorSample {
  TimeNs t_ns = 0;
  std::vector<double> speeds;
};

/// @brief Directly measured collective thrust along body z [N].
struct ThrustSample {
  TimeNs t_ns = 0;
  double thrust_N = 0.0;
};

/// @brief One image (lazy: only the path; decoding is the consumer's business).
struct ImageRef {
  int cam_id = 0;
  std::string path;  ///< absolute path of the PNG
};

/// @brief All camera images sharing one timestamp (mono: one entry; stereo: two).
struct ImageFrame {
  TimeNs t_ns = 0;
  std::vector<ImageRef> images;  ///< sorted by cam_id
};

/// @brief One feature observation in one camera.
struct FeatureObservation {
  int cam_id = 0;
  std::uint64_t feature_id = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();       ///< distorted pixel [px]
  Eigen::Vector2d uv_norm = Eigen::Vector2d::Zero();  ///< undistorted normalized (x/z, y/z)
  bool has_norm = false;  ///< false until a camera model has undistorted uv
};

/// @brief All feature observations of one camera time (all cameras).
struct FeatureFrame {
  TimeNs t_ns = 0;
  std::vector<FeatureObservation> observations;
};

/// @brief Ground-truth external force in WORLD frame [N] (force0), optionally with its rate
/// (force0 files of 7 columns; older 4-column files have none).
struct ForceSample {
  TimeNs t_ns = 0;
  Eigen::Vector3d f_W_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d df_W_Nps = Eigen::Vector3d::Zero();  ///< dF/dt [N/s], W; zero when absent
  bool has_rate = false;                               ///< df_W_Nps was given
};

/// @brief Ground-truth mass [kg] (mass0).
struct MassSample {
  TimeNs t_ns = 0;
  double mass_kg = 0.0;
};

/// @brief Ground-truth state, EuRoC state_groundtruth_estimate0 columns (R = W, S = I).
struct GroundTruthSample {
  TimeNs t_ns = 0;
  Pose T_WI;  ///< p_RS, q_RS
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();
};

/// @brief Anything a time-ordered measurement stream can carry.
using Measurement = std::variant<ImuSample, RotorSample, ThrustSample, ImageFrame, FeatureFrame,
                                 ForceSample, MassSample, GroundTruthSample>;

/// @brief Timestamp of any measurement.
inline TimeNs stamp_of(const Measurement& m) {
  return std::visit([](const auto& x) { return x.t_ns; }, m);
}

}  // namespace vid
