#pragma once
/// @file reference_trajectory.h
/// @brief The study's reference trajectories (seed section 5.3): random, loop, lemniscate,
/// zigzag, square. Sizes, speeds and periods are in study_config.h / dynamics/massid/README.md
/// "Data generation".
///
/// Every trajectory starts at rest in hover: the base path p(tau) is run through a time warp
/// tau(t) whose rate rises smoothly from 0 to 1 over `ramp_s`, so v, a start at zero.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>

#include "massid/gen/study_config.h"

namespace vid::massid::gen {

/// @brief Reference at one time: position, velocity, acceleration and jerk in W, yaw [rad].
struct RefPoint {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d j_W = Eigen::Vector3d::Zero();
  double yaw = 0.0;
};

/// @brief A reference trajectory, smooth (C^2) in time.
class ReferenceTrajectory {
 public:
  virtual ~ReferenceTrajectory() = default;
  /// @brief Reference at t [s] (t >= 0).
  virtual RefPoint at(double t_s) const = 0;
};

/// @brief Build trajectory `name` (random | loop | lemniscate | zigzag | square). Only `random`
/// uses the seed (its sinusoids' amplitudes, frequencies and phases).
/// @throws std::invalid_argument on an unknown name
std::unique_ptr<ReferenceTrajectory> make_reference_trajectory(const std::string& name,
                                                               const TrajectorySettings& settings,
                                                               std::uint64_t seed);

}  // namespace vid::massid::gen
