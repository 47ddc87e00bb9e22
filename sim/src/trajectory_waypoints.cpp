/// @file trajectory_waypoints.cpp
/// @brief Square, zigzag and vertical steps (rest-to-rest septic segments between corners,
/// an optional rest at each, repeated),
/// random smooth waypoints in a box and TUM-file trajectories (quintic B-splines).

#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "bspline.h"
#include "io/csv_reader.h"
#include "sim/render/random.h"
#include "sim/trajectory.h"
#include "smooth_profile.h"
#include "trajectory_impl.h"

namespace vid::sim::detail {

namespace {

/// @brief Closed polygon flown corner to corner, stopping at each corner (and resting there
/// hold_s; the rest follows each move, so hold_s = 0 flies exactly the path without it).
class RestToRest : public Trajectory {
 public:
  RestToRest(const TrajectoryConfig& c, std::vector<Eigen::Vector3d> corners)
      : c_(c), corners_(std::move(corners)) {
    if (!(c.max_speed > 0.0) || !(c.max_accel > 0.0))
      throw std::invalid_argument("trajectory: max_speed and max_accel must be > 0");
    if (!(c.hold_s >= 0.0)) throw std::invalid_argument("trajectory: hold_s must be >= 0");
    double t = 0.0;
    for (std::size_t i = 0; i < corners_.size(); ++i) {
      const double L = (corners_[(i + 1) % corners_.size()] - corners_[i]).norm();
      const double T = smoothstep_duration(L, c.max_speed, c.max_accel);
      starts_.push_back(t);
      durations_.push_back(T);
      t += T + c.hold_s;
    }
    period_ = t;
  }

  FlatOutput eval(double t) const override {
    FlatOutput o;
    o.yaw = c_.yaw0;
    double tau = t - c_.start_delay_s;
    if (tau <= 0.0) {
      o.p = corners_.front();
      return o;
    }
    tau = std::fmod(tau, period_);
    std::size_t i = 0;
    while (i + 1 < starts_.size() && tau >= starts_[i + 1]) ++i;
    const double T = durations_[i];
    const Eigen::Vector3d d = corners_[(i + 1) % corners_.size()] - corners_[i];
    const auto S = smoothstep7((tau - starts_[i]) / T);  // clamped: at rest past the move
    o.p = corners_[i] + d * S[0];
    o.v = d * S[1] / T;
    o.a = d * S[2] / (T * T);
    o.j = d * S[3] / (T * T * T);
    o.s = d * S[4] / (T * T * T * T);
    return o;
  }

 private:
  TrajectoryConfig c_;
  std::vector<Eigen::Vector3d> corners_;
  std::vector<double> starts_, durations_;
  double period_ = 0.0;
};

/// @brief Position (and optionally yaw) B-splines, time-scaled to the limits.
class SplineTrajectory : public Trajectory {
 public:
  SplineTrajectory(UniformBSpline pos, UniformBSpline yaw, double delay)
      : pos_(std::move(pos)), yaw_(std::move(yaw)), delay_(delay) {}

  FlatOutput eval(double t) const override {
    const double tau = pos_.t_begin() + std::max(0.0, t - delay_);
    const auto P = pos_.eval(tau);
    const auto Y = yaw_.eval(tau);
    FlatOutput o;
    o.p = P[0];
    o.v = P[1];
    o.a = P[2];
    o.j = P[3];
    o.s = P[4];
    o.yaw = Y[0][0];
    o.yaw_rate = Y[1][0];
    o.yaw_acc = Y[2][0];
    if (t < delay_) {  // hovering before the start: derivatives of a held point vanish
      o.v.setZero(), o.a.setZero(), o.j.setZero(), o.s.setZero();
      o.yaw_rate = o.yaw_acc = 0.0;
    }
    return o;
  }
  double duration_s() const override { return delay_ + pos_.t_end() - pos_.t_begin(); }

 private:
  UniformBSpline pos_, yaw_;
  double delay_;
};

/// @brief Scale factor >= (peak/limit) so that the curve respects max speed / accel.
double time_scale(const UniformBSpline& s, double vmax, double amax) {
  double v = 0.0, a = 0.0;
  const double step = s.dt() / 20.0;
  for (double t = s.t_begin(); t <= s.t_end(); t += step) {
    const auto d = s.eval(t);
    v = std::max(v, d[1].norm());
    a = std::max(a, d[2].norm());
  }
  return std::max(v / vmax, std::sqrt(a / amax));
}

}  // namespace

std::unique_ptr<Trajectory> make_square(const TrajectoryConfig& c) {
  const double r = c.radius_m;
  if (!(r > 0.0)) throw std::invalid_argument("trajectory: radius (half side) must be > 0");
  std::vector<Eigen::Vector3d> corners = {c.center + Eigen::Vector3d(r, r, 0), c.center + Eigen::Vector3d(-r, r, 0),
                                          c.center + Eigen::Vector3d(-r, -r, 0), c.center + Eigen::Vector3d(r, -r, 0)};
  return std::make_unique<RestToRest>(c, corners);
}

std::unique_ptr<Trajectory> make_zigzag(const TrajectoryConfig& c) {
  if (c.zigzag_legs < 2) throw std::invalid_argument("trajectory: zigzag_legs must be >= 2");
  // Forward along x alternating y, then back the same way (closed path).
  std::vector<Eigen::Vector3d> fwd;
  for (int i = 0; i <= c.zigzag_legs; ++i) {
    const double x = -0.5 * c.zigzag_length_m + c.zigzag_length_m * i / c.zigzag_legs;
    const double y = (i % 2 == 0 ? -0.5 : 0.5) * c.zigzag_width_m;
    fwd.push_back(c.center + Eigen::Vector3d(x, y, 0.0));
  }
  std::vector<Eigen::Vector3d> corners = fwd;
  for (int i = c.zigzag_legs - 1; i >= 1; --i) corners.push_back(fwd[i]);
  return std::make_unique<RestToRest>(c, corners);
}

std::unique_ptr<Trajectory> make_vertical_steps(const TrajectoryConfig& c) {
  if (c.step_heights_m.empty()) throw std::invalid_argument("trajectory: vertical_steps needs step_heights_m");
  // From the centre up or down to each level in turn and back to the centre: the collective
  // thrust steps above and below the weight (the thrust-coefficient fit's log, vid-fit-thrust).
  std::vector<Eigen::Vector3d> corners = {c.center};
  for (const double z : c.step_heights_m) {
    if (std::abs(z - corners.back().z()) < 1e-6 || std::abs(z - c.center.z()) < 1e-6)
      throw std::invalid_argument("trajectory: step_heights_m: each level must differ from the previous one and the centre");
    corners.push_back(Eigen::Vector3d(c.center.x(), c.center.y(), z));
  }
  return std::make_unique<RestToRest>(c, corners);
}

std::unique_ptr<Trajectory> make_random(const TrajectoryConfig& c) {
  if (!(c.waypoint_spacing_s > 0.0)) throw std::invalid_argument("trajectory: waypoint_spacing_s must be > 0");
  if (!((c.box_max - c.box_min).minCoeff() >= 0.0)) throw std::invalid_argument("trajectory: box_min > box_max");
  Rng rng(derive_seed(c.seed, 0x7472616aULL));
  // Control points for at least 600 s: shorter runs (--duration) fly a prefix of the same path.
  const int n_random = static_cast<int>(std::ceil(2.0 * std::max(c.duration_s, 600.0) / c.waypoint_spacing_s)) + 4;
  const int clamp = UniformBSpline::kDegree + 1;
  Eigen::MatrixXd P(3, n_random + 2 * clamp);
  Eigen::MatrixXd Y(1, n_random + 2 * clamp);
  // Start (and end) clamped at the box centre at rest; the first random points pull away.
  const Eigen::Vector3d start = 0.5 * (c.box_min + c.box_max);
  for (int i = 0; i < P.cols(); ++i) {
    const bool clamped = i < clamp || i >= clamp + n_random;
    Eigen::Vector3d p = start;
    double yaw = c.yaw0;
    if (!clamped) {
      for (int k = 0; k < 3; ++k) p[k] = rng.uniform(c.box_min[k], c.box_max[k]);
      yaw = c.yaw0 + rng.uniform(-c.random_yaw_amplitude, c.random_yaw_amplitude);
    }
    P.col(i) = p;
    Y(0, i) = yaw;
  }
  UniformBSpline nominal(P, 0.0, c.waypoint_spacing_s);
  const double lambda = time_scale(nominal, c.max_speed, c.max_accel);
  const double dt = c.waypoint_spacing_s * lambda;
  return std::make_unique<SplineTrajectory>(UniformBSpline(P, 0.0, dt), UniformBSpline(Y, 0.0, dt),
                                            c.start_delay_s);
}

std::unique_ptr<Trajectory> make_from_file(const TrajectoryConfig& c) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(c.file, ec)) {
    throw std::invalid_argument("trajectory: cannot open TUM file '" + c.file + "'");
  }
  io::CsvReader in(c.file, ' ');  // TUM: "t x y z qx qy qz qw", blank separated
  std::vector<double> times;
  std::vector<Eigen::Vector4d> rows;  // x, y, z, yaw
  double prev_yaw = 0.0;
  static constexpr std::array<const char*, 8> kColumns = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
  while (in.next_row()) {
    if (in.size() < kColumns.size()) in.fail("expected 8 numbers (TUM)");
    std::array<double, 8> v{};
    for (std::size_t i = 0; i < kColumns.size(); ++i) v[i] = in.get_double(i, kColumns[i]);
    const auto [t, x, y, z, qx, qy, qz, qw] = v;
    if (!times.empty() && !(t > times.back())) in.fail("timestamps not increasing");
    double yaw = std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz));
    if (!rows.empty()) yaw = prev_yaw + std::remainder(yaw - prev_yaw, 2.0 * M_PI);  // unwrap
    prev_yaw = yaw;
    times.push_back(t);
    rows.emplace_back(x, y, z, yaw);
  }
  if (times.size() < 10) throw std::invalid_argument(c.file + ": need at least 10 poses");
  Eigen::MatrixXd P(3, static_cast<Eigen::Index>(rows.size())), Y(1, static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    P.col(static_cast<Eigen::Index>(k)) = rows[k].head<3>();
    Y(0, static_cast<Eigen::Index>(k)) = rows[k][3];
  }
  const UniformBSpline pos = UniformBSpline::fit(times, P, c.fit_knot_spacing_s);
  const UniformBSpline yaw = UniformBSpline::fit(times, Y, c.fit_knot_spacing_s);
  // Slow down (never speed up) when the recorded motion exceeds the limits.
  const double lambda = std::max(1.0, time_scale(pos, c.max_speed, c.max_accel));
  const double dt = c.fit_knot_spacing_s * lambda;
  return std::make_unique<SplineTrajectory>(UniformBSpline(pos.control(), 0.0, dt),
                                            UniformBSpline(yaw.control(), 0.0, dt), 0.0);
}

}  // namespace vid::sim::detail
