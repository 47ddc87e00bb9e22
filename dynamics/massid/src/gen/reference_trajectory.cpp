/// @file reference_trajectory.cpp
/// @brief Sinusoid-sum paths (random, loop, lemniscate) and rest-to-rest minimum-jerk waypoint
/// paths (zigzag, square), all behind a smooth start-up time warp.
#include "massid/gen/reference_trajectory.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "massid/gen/rng.h"

namespace vid::massid::gen {
namespace {

/// d^k p / d tau^k for k = 0..3.
using Derivs = std::array<Eigen::Vector3d, 4>;

class BasePath {
 public:
  virtual ~BasePath() = default;
  virtual Derivs derivs(double tau) const = 0;
};

/// p_i(tau) = c_i + sum_j A_j sin(w_j tau + phi_j), per axis i.
class SinusoidPath : public BasePath {
 public:
  struct Term {
    double amplitude, omega, phase;
  };
  SinusoidPath(const Eigen::Vector3d& center, std::array<std::vector<Term>, 3> terms)
      : center_(center), terms_(std::move(terms)) {}
  Derivs derivs(double tau) const override {
    Derivs d;
    for (auto& x : d) x.setZero();
    d[0] = center_;
    for (int axis = 0; axis < 3; ++axis) {
      for (const Term& term : terms_[axis]) {
        const double arg = term.omega * tau + term.phase;
        const double s = std::sin(arg), c = std::cos(arg);
        const double w = term.omega, A = term.amplitude;
        d[0][axis] += A * s;
        d[1][axis] += A * w * c;
        d[2][axis] -= A * w * w * s;
        d[3][axis] -= A * w * w * w * c;
      }
    }
    return d;
  }

 private:
  Eigen::Vector3d center_;
  std::array<std::vector<Term>, 3> terms_;
};

/// Closed polygon of waypoints, each leg a rest-to-rest quintic s(u) = 10u^3 - 15u^4 + 6u^5
/// (minimum jerk): peak speed 1.875 L/T, peak acceleration 5.77 L/T^2 on a leg of length L.
class WaypointPath : public BasePath {
 public:
  WaypointPath(std::vector<Eigen::Vector3d> waypoints, double leg_s)
      : wp_(std::move(waypoints)), leg_s_(leg_s) {}
  Derivs derivs(double tau) const override {
    const int n = static_cast<int>(wp_.size());
    const double legs = tau / leg_s_;
    const long k = static_cast<long>(std::floor(legs));
    const double u = legs - static_cast<double>(k);
    const int i = static_cast<int>(((k % n) + n) % n);
    const Eigen::Vector3d a = wp_[i];
    const Eigen::Vector3d delta = wp_[(i + 1) % n] - a;
    const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
    const double s0 = 10 * u3 - 15 * u4 + 6 * u5;
    const double s1 = (30 * u2 - 60 * u3 + 30 * u4) / leg_s_;
    const double s2 = (60 * u - 180 * u2 + 120 * u3) / (leg_s_ * leg_s_);
    const double s3 = (60 - 360 * u + 360 * u2) / (leg_s_ * leg_s_ * leg_s_);
    return {a + delta * s0, delta * s1, delta * s2, delta * s3};
  }

 private:
  std::vector<Eigen::Vector3d> wp_;
  double leg_s_;
};

/// tau(t) with tau' = (1 - cos(pi t / T_r)) / 2 on [0, T_r], then 1: starts at rest.
class WarpedTrajectory : public ReferenceTrajectory {
 public:
  WarpedTrajectory(std::unique_ptr<BasePath> path, double ramp_s)
      : path_(std::move(path)), ramp_s_(ramp_s) {}
  RefPoint at(double t) const override {
    double tau = t, t1 = 1.0, t2 = 0.0, t3 = 0.0;
    if (ramp_s_ > 0.0 && t < ramp_s_) {
      const double w = M_PI / ramp_s_;
      tau = 0.5 * t - std::sin(w * t) / (2.0 * w);
      t1 = 0.5 * (1.0 - std::cos(w * t));
      t2 = 0.5 * w * std::sin(w * t);
      t3 = 0.5 * w * w * std::cos(w * t);
    } else if (ramp_s_ > 0.0) {
      tau = t - 0.5 * ramp_s_;
    }
    const Derivs d = path_->derivs(tau);
    RefPoint r;
    r.p_W = d[0];
    r.v_W = d[1] * t1;
    r.a_W = d[2] * t1 * t1 + d[1] * t2;
    r.j_W = d[3] * t1 * t1 * t1 + 3.0 * d[2] * t1 * t2 + d[1] * t3;
    return r;
  }

 private:
  std::unique_ptr<BasePath> path_;
  double ramp_s_;
};

std::unique_ptr<BasePath> random_path(const TrajectorySettings& s, std::uint64_t seed) {
  Rng rng(seed ^ 0x7261'6E64'6F6Dull);  // own stream, independent of the noise stream
  std::array<std::vector<SinusoidPath::Term>, 3> terms;
  for (int axis = 0; axis < 3; ++axis) {
    const double accel_bound = axis < 2 ? s.random_accel_xy : s.random_accel_z;
    const double amplitude_bound = axis < 2 ? s.random_amplitude_xy : s.random_amplitude_z;
    double peak_accel = 0.0, peak_offset = 0.0;
    for (int j = 0; j < 3; ++j) {
      SinusoidPath::Term term;
      term.omega = 2.0 * M_PI * rng.uniform(s.random_freq_min_hz, s.random_freq_max_hz);
      term.amplitude = rng.uniform(0.3, 1.0);
      term.phase = rng.uniform(0.0, 2.0 * M_PI);
      peak_accel += term.amplitude * term.omega * term.omega;
      peak_offset += term.amplitude;
      terms[axis].push_back(term);
    }
    // Scale so the worst-case sums reach the acceleration bound or the size bound, whichever
    // comes first (slow draws would otherwise wander far).
    const double scale = std::min(accel_bound / peak_accel, amplitude_bound / peak_offset);
    for (auto& term : terms[axis]) term.amplitude *= scale;
  }
  // Centred on (0, 0, altitude); the start point depends on the phases.
  return std::make_unique<SinusoidPath>(Eigen::Vector3d(0, 0, s.altitude_m), terms);
}

}  // namespace

std::unique_ptr<ReferenceTrajectory> make_reference_trajectory(const std::string& name,
                                                               const TrajectorySettings& s,
                                                               std::uint64_t seed) {
  std::unique_ptr<BasePath> path;
  if (name == "loop") {
    const double w = 2.0 * M_PI / s.loop_period_s;
    std::array<std::vector<SinusoidPath::Term>, 3> terms;
    terms[0] = {{s.loop_radius_m, w, M_PI / 2}};  // R cos(w tau)
    terms[1] = {{s.loop_radius_m, w, 0.0}};
    terms[2] = {{s.loop_z_amplitude_m, 2.0 * w, 0.0}};
    path = std::make_unique<SinusoidPath>(Eigen::Vector3d(0, 0, s.altitude_m), terms);
  } else if (name == "lemniscate") {
    // Lemniscate of Gerono: x = A sin(w tau), y = A/2 sin(2 w tau).
    const double w = 2.0 * M_PI / s.lemniscate_period_s;
    std::array<std::vector<SinusoidPath::Term>, 3> terms;
    terms[0] = {{s.lemniscate_size_m, w, 0.0}};
    terms[1] = {{0.5 * s.lemniscate_size_m, 2.0 * w, 0.0}};
    path = std::make_unique<SinusoidPath>(Eigen::Vector3d(0, 0, s.altitude_m), terms);
  } else if (name == "zigzag") {
    // Four legs forward, four back; y and z alternate at every corner.
    std::vector<Eigen::Vector3d> wp;
    const double x0 = -2.0 * s.zigzag_dx_m;
    for (int k = 0; k < 8; ++k) {
      const int step = k <= 4 ? k : 8 - k;
      const double sign = (k % 2 == 0) ? -0.5 : 0.5;
      wp.emplace_back(x0 + step * s.zigzag_dx_m, sign * s.zigzag_dy_m,
                      s.altitude_m + sign * s.zigzag_dz_m);
    }
    path = std::make_unique<WaypointPath>(wp, s.zigzag_leg_s);
  } else if (name == "square") {
    const double h = 0.5 * s.square_side_m;
    std::vector<Eigen::Vector3d> wp = {{-h, -h, s.altitude_m},
                                       {h, -h, s.altitude_m},
                                       {h, h, s.altitude_m},
                                       {-h, h, s.altitude_m}};
    path = std::make_unique<WaypointPath>(wp, s.square_leg_s);
  } else if (name == "random") {
    path = random_path(s, seed);
  } else {
    throw std::invalid_argument("unknown trajectory '" + name +
                                "' (random, loop, lemniscate, zigzag, square)");
  }
  return std::make_unique<WarpedTrajectory>(std::move(path), s.ramp_s);
}

}  // namespace vid::massid::gen
