#pragma once
/// @file calibration.h
/// @brief Sensor calibration and vehicle parameters shared by io, sim, frontend and the
/// estimator. Plain data, Eigen only; loading/validation lives in io.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace vid {

/// @brief The one default gravity magnitude [m/s^2] (g_W = [0, 0, -g]): every struct with a
/// gravity field starts from it; a vehicle.yaml or study config gives the vehicle's own.
inline constexpr double kDefaultGravity = 9.81;

/// @brief Distortion models (Kalibr names: radtan, equidistant).
enum class DistortionModel { kNone, kRadTan, kEquidistant };

/// @brief One camera: intrinsics, distortion and pose in the IMU frame.
struct CameraCalib {
  int cam_id = 0;
  int width = 640;
  int height = 480;
  Eigen::Vector4d intrinsics{400.0, 400.0, 320.0, 240.0};  ///< fu, fv, cu, cv
  DistortionModel distortion = DistortionModel::kRadTan;
  /// radtan: k1, k2, p1, p2; equidistant: k1, k2, k3, k4
  Eigen::Vector4d distortion_coeffs = Eigen::Vector4d::Zero();
  Eigen::Isometry3d T_IC = Eigen::Isometry3d::Identity();  ///< pose of camera C in I
  double timeshift_cam_imu_s = 0.0;  ///< t_imu = t_cam + timeshift (Kalibr)
  double rate_hz = 30.0;
};

/// @brief IMU noise, Kalibr/EuRoC continuous-time parameters. The defaults are the one default
/// of each quantity: the VID-Dataset-like IMU of config/sim/vid17_like.yaml. EstimatorParams
/// starts from them, and the simulator's scenario reader uses them for a key it is not given.
struct ImuNoise {
  double gyro_noise_density = 1.0e-3;      ///< rad/s/sqrt(Hz)
  double gyro_random_walk = 3.5e-5;        ///< rad/s^2/sqrt(Hz)
  double accel_noise_density = 0.1;        ///< m/s^2/sqrt(Hz)
  double accel_random_walk = 4.0e-3;       ///< m/s^3/sqrt(Hz)
  double rate_hz = 400.0;
  Eigen::Isometry3d T_BS = Eigen::Isometry3d::Identity();  ///< IMU in body (identity here)
};

/// @brief Rotor speed sensor (rotor0/sensor.yaml).
struct RotorSensor {
  std::string unit = "rpm";  ///< "rpm" or "rad/s"
  int count = 4;
  double rate_hz = 100.0;
  double noise_density = 1.459;  ///< unit / sqrt(Hz)
};

/// @brief Vehicle parameters (vehicle.yaml).
struct VehicleParams {
  double mass_kg = 1.0;
  double gravity = kDefaultGravity;  ///< [m/s^2]
  std::vector<double> rotor_thrust_coefficients;  ///< k_i [N / unit^2], T_i = k_i n_i^2
  /// Mass-normalized linear body drag D [1/s]: the rotors' drag F_I = -diag(D) v_I that the
  /// dynamics model predicts (docs/design.md §3 "Rotor drag"); zero = no drag model.
  Eigen::Vector3d linear_drag = Eigen::Vector3d::Zero();
  /// Direction of the collective thrust in I (unit vector): a real thrust axis sits 1-2 deg off
  /// the IMU's z axis (mounting, frame flex).
  Eigen::Vector3d thrust_axis_I = Eigen::Vector3d::UnitZ();
};

}  // namespace vid
