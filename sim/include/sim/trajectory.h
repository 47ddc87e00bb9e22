#pragma once
/// @file trajectory.h
/// @brief Reference trajectories as flat outputs (position and its first four derivatives,
/// yaw and its first two derivatives) for a differentially flat multirotor.

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace vid::sim {

/// @brief Flat output at one time: p, v, a, jerk, snap in W, yaw and its rates.
struct FlatOutput {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d j = Eigen::Vector3d::Zero();
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  double yaw_rate = 0.0;
  double yaw_acc = 0.0;
};

/// @brief A reference trajectory; t in seconds from the start of the run.
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  /// @brief Flat output at t (t < 0 is the initial point, t > duration the final one).
  virtual FlatOutput eval(double t_s) const = 0;
  /// @brief Length of the designed motion (infinity for periodic paths).
  virtual double duration_s() const { return std::numeric_limits<double>::infinity(); }
};

/// @brief Yaw behaviour of periodic paths.
enum class YawMode { kFixed, kFollow, kRate };

/// @brief Parameters of every trajectory type (unused fields are ignored by a type).
struct TrajectoryConfig {
  std::string type = "hover";  ///< hover, circle, lemniscate, zigzag, square, vertical_steps, random, file
  Eigen::Vector3d center{0.0, 0.0, 1.2};   ///< W [m]
  double radius_m = 1.0;                   ///< circle radius, lemniscate half-width, square half-side
  double height_amplitude_m = 0.0;         ///< circle/lemniscate vertical oscillation
  double max_speed = 1.0;                  ///< [m/s] nominal cruise speed and limit
  double max_accel = 2.0;                  ///< [m/s^2] limit
  double ramp_s = 3.0;                     ///< smooth start of periodic paths
  double start_delay_s = 1.0;              ///< hover before moving
  YawMode yaw_mode = YawMode::kFixed;
  double yaw0 = 0.0;                       ///< initial / fixed yaw [rad]
  double yaw_rate = 0.0;                   ///< for YawMode::kRate [rad/s]
  // zigzag
  double zigzag_length_m = 4.0;            ///< extent along x
  double zigzag_width_m = 1.5;             ///< extent along y
  int zigzag_legs = 6;
  // vertical_steps: rest-to-rest climbs and descents over the centre, levels flown in turn
  std::vector<double> step_heights_m;      ///< z of the levels [m] (W), cycled after the centre
  double hold_s = 0.0;                     ///< rest at each level (and zigzag/square corner) [s]
  // random waypoints
  Eigen::Vector3d box_min{-2.0, -2.0, 0.8};
  Eigen::Vector3d box_max{2.0, 2.0, 2.0};
  double waypoint_spacing_s = 2.0;         ///< control point spacing before time scaling
  double random_yaw_amplitude = 0.0;       ///< random smooth yaw within +-amplitude [rad]
  // file
  std::string file;                        ///< TUM pose file (timestamp tx ty tz qx qy qz qw)
  double fit_knot_spacing_s = 0.25;        ///< B-spline knot spacing for the fit
  double duration_s = 60.0;                ///< total length for finite trajectories (random)
  std::uint64_t seed = 1;                  ///< random waypoints
};

/// @brief Build a trajectory (throws std::invalid_argument on bad parameters).
std::unique_ptr<Trajectory> make_trajectory(const TrajectoryConfig& config);

/// @brief Largest speed and acceleration of a trajectory sampled over [t0, t1] every dt.
void trajectory_extremes(const Trajectory& traj, double t0, double t1, double dt,
                         double* max_speed, double* max_accel);

}  // namespace vid::sim
