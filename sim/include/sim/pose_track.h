#pragma once
/// @file pose_track.h
/// @brief A recorded body trajectory T_WI(t) (e.g. motion capture, read from a TUM file) and
/// its interpolation between the samples: the pose and the BodyMotion that vid_sim
/// --camera-along renders and simulates features at (config/sim/README.md "Cameras along a
/// recorded trajectory").
///
/// Interpolation: position by a natural cubic spline through every sample (C2: the camera sees
/// exactly the recorded positions at the sample times, and velocity and acceleration - what the
/// renderer's motion blur and rolling shutter extrapolate with - are continuous; linear
/// interpolation would make the velocity jump at every sample and the acceleration zero);
/// rotation by slerp between neighbouring samples, so the body rate is constant within a
/// sample interval (the slerp's own rate).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <filesystem>
#include <vector>

#include "sim/simulator.h"
#include "types/measurements.h"

namespace vid::sim {

/// @brief Recorded poses T_WI at strictly increasing times, interpolated in between.
class PoseTrack {
 public:
  /// @brief Largest accepted | |q| - 1 | of a recorded quaternion (TUM files written with a
  /// few decimals); within it the quaternion is normalized.
  static constexpr double kUnitTolerance = 1e-3;

  /// @brief From samples (at least 2; times strictly increasing; unit quaternions within
  /// kUnitTolerance). Throws std::invalid_argument naming the sample index otherwise.
  PoseTrack(std::vector<TimeNs> t_ns, std::vector<Eigen::Vector3d> p_WI, std::vector<Eigen::Quaterniond> q_WI);

  /// @brief Read a TUM file `t[s] x y z qx qy qz qw` (blank-separated, '#' comments) through
  /// io::CsvReader: exactly 8 numbers per row, stamps >= 0 converted to ns from their decimal
  /// text (exact to the ns), strictly increasing, unit quaternions. Any violation throws
  /// io::DatasetError "FILE:LINE: ..." (with the column where one is at fault).
  static PoseTrack read_tum(const std::filesystem::path& file);

  TimeNs start_ns() const { return t_ns_.front(); }
  TimeNs end_ns() const { return t_ns_.back(); }
  std::size_t size() const { return t_ns_.size(); }

  /// @brief Interpolated pose T_WI at @p t_ns in [start_ns, end_ns] (clamped outside).
  Eigen::Isometry3d pose(TimeNs t_ns) const;
  /// @brief Interpolated motion at @p t_ns: velocity and acceleration of the spline, body rate
  /// of the slerp interval containing t (the later interval at a sample time).
  BodyMotion motion(TimeNs t_ns) const;

 private:
  /// Index i of the interval [t_i, t_i+1] containing t (clamped to the valid range).
  std::size_t interval(TimeNs t_ns) const;
  double seconds(TimeNs t_ns) const { return static_cast<double>(t_ns - t_ns_.front()) * 1e-9; }

  std::vector<TimeNs> t_ns_;
  std::vector<double> t_s_;                   ///< seconds after the first sample
  std::vector<Eigen::Vector3d> p_;            ///< recorded positions
  std::vector<Eigen::Vector3d> m_;            ///< spline second derivatives at the samples
  std::vector<Eigen::Quaterniond> q_;         ///< recorded orientations (normalized)
  std::vector<Eigen::Vector3d> w_I_;          ///< slerp body rate of interval i [rad/s]
};

}  // namespace vid::sim
