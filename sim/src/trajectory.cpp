#include "sim/trajectory.h"

#include <stdexcept>

#include "trajectory_impl.h"

namespace vid::sim {

std::unique_ptr<Trajectory> make_trajectory(const TrajectoryConfig& c) {
  if (c.type == "hover") return detail::make_hover(c);
  if (c.type == "circle") return detail::make_circle(c);
  if (c.type == "lemniscate") return detail::make_lemniscate(c);
  if (c.type == "square") return detail::make_square(c);
  if (c.type == "zigzag") return detail::make_zigzag(c);
  if (c.type == "vertical_steps") return detail::make_vertical_steps(c);
  if (c.type == "random") return detail::make_random(c);
  if (c.type == "file") return detail::make_from_file(c);
  throw std::invalid_argument("trajectory: unknown type '" + c.type +
                              "' (hover, circle, lemniscate, square, zigzag, vertical_steps, random, file)");
}

void trajectory_extremes(const Trajectory& traj, double t0, double t1, double dt, double* max_speed,
                         double* max_accel) {
  *max_speed = 0.0;
  *max_accel = 0.0;
  for (double t = t0; t <= t1; t += dt) {
    const FlatOutput o = traj.eval(t);
    *max_speed = std::max(*max_speed, o.v.norm());
    *max_accel = std::max(*max_accel, o.a.norm());
  }
}

}  // namespace vid::sim
