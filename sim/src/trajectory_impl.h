#pragma once
/// @file trajectory_impl.h
/// @brief Constructors of the concrete trajectories (private to sim).

#include <memory>

#include "sim/trajectory.h"

namespace vid::sim::detail {

std::unique_ptr<Trajectory> make_hover(const TrajectoryConfig& c);
std::unique_ptr<Trajectory> make_circle(const TrajectoryConfig& c);
std::unique_ptr<Trajectory> make_lemniscate(const TrajectoryConfig& c);
std::unique_ptr<Trajectory> make_square(const TrajectoryConfig& c);
std::unique_ptr<Trajectory> make_zigzag(const TrajectoryConfig& c);
std::unique_ptr<Trajectory> make_vertical_steps(const TrajectoryConfig& c);
std::unique_ptr<Trajectory> make_random(const TrajectoryConfig& c);
std::unique_ptr<Trajectory> make_from_file(const TrajectoryConfig& c);

}  // namespace vid::sim::detail
