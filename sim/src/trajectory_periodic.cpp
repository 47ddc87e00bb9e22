/// @file trajectory_periodic.cpp
/// @brief Hover, circle and lemniscate: a curve f(theta) traversed with a smoothly ramped
/// phase theta(t) = omega * phi(t), derivatives by the chain rule (Faa di Bruno).

#include <cmath>
#include <stdexcept>

#include "sim/trajectory.h"
#include "smooth_profile.h"
#include "trajectory_impl.h"

namespace vid::sim::detail {

namespace {

/// @brief A closed curve and its first four derivatives w.r.t. theta.
using CurveDerivs = std::array<Eigen::Vector3d, 5>;

class PhaseCurve : public Trajectory {
 public:
  PhaseCurve(const TrajectoryConfig& c, bool lemniscate) : c_(c), lemniscate_(lemniscate) {
    if (!(c.radius_m > 0.0)) throw std::invalid_argument("trajectory: radius must be > 0");
    if (!(c.max_speed > 0.0) || !(c.max_accel > 0.0))
      throw std::invalid_argument("trajectory: max_speed and max_accel must be > 0");
    // omega from the speed and acceleration limits over one period of the curve.
    double d1 = 0.0, d2 = 0.0;
    for (int i = 0; i < 2000; ++i) {
      const CurveDerivs f = curve(2.0 * M_PI * i / 2000.0);
      d1 = std::max(d1, f[1].norm());
      d2 = std::max(d2, f[2].norm());
    }
    omega_ = std::min(c.max_speed / d1, std::sqrt(c.max_accel / d2));
  }

  FlatOutput eval(double t) const override {
    const auto ph = ramp_phase(t - c_.start_delay_s, c_.ramp_s);
    const double th = omega_ * ph[0], th1 = omega_ * ph[1], th2 = omega_ * ph[2],
                 th3 = omega_ * ph[3], th4 = omega_ * ph[4];
    const CurveDerivs f = curve(th);
    FlatOutput o;
    o.p = f[0];
    o.v = f[1] * th1;
    o.a = f[2] * th1 * th1 + f[1] * th2;
    o.j = f[3] * th1 * th1 * th1 + 3.0 * f[2] * th1 * th2 + f[1] * th3;
    o.s = f[4] * std::pow(th1, 4) + 6.0 * f[3] * th1 * th1 * th2 + 3.0 * f[2] * th2 * th2 +
          4.0 * f[2] * th1 * th3 + f[1] * th4;
    switch (c_.yaw_mode) {
      case YawMode::kFixed:
        o.yaw = c_.yaw0;
        break;
      case YawMode::kFollow:  // circle only (checked by the factory): tangent heading
        o.yaw = c_.yaw0 + th;
        o.yaw_rate = th1;
        o.yaw_acc = th2;
        break;
      case YawMode::kRate:
        o.yaw = c_.yaw0 + c_.yaw_rate * ph[0];
        o.yaw_rate = c_.yaw_rate * ph[1];
        o.yaw_acc = c_.yaw_rate * ph[2];
        break;
    }
    return o;
  }

 private:
  CurveDerivs curve(double th) const {
    const double r = c_.radius_m, h = c_.height_amplitude_m;
    const double s = std::sin(th), co = std::cos(th);
    CurveDerivs f;
    if (!lemniscate_) {
      f[0] = c_.center + Eigen::Vector3d(r * co, r * s, h * s);
      f[1] = Eigen::Vector3d(-r * s, r * co, h * co);
      f[2] = Eigen::Vector3d(-r * co, -r * s, -h * s);
      f[3] = Eigen::Vector3d(r * s, -r * co, -h * co);
      f[4] = Eigen::Vector3d(r * co, r * s, h * s);
    } else {
      // Gerono lemniscate: x = r sin(th), y = r/2 sin(2 th), z = h sin(2 th).
      const double s2 = std::sin(2 * th), c2 = std::cos(2 * th);
      f[0] = c_.center + Eigen::Vector3d(r * s, 0.5 * r * s2, h * s2);
      f[1] = Eigen::Vector3d(r * co, r * c2, 2 * h * c2);
      f[2] = Eigen::Vector3d(-r * s, -2 * r * s2, -4 * h * s2);
      f[3] = Eigen::Vector3d(-r * co, -4 * r * c2, -8 * h * c2);
      f[4] = Eigen::Vector3d(r * s, 8 * r * s2, 16 * h * s2);
    }
    return f;
  }

  TrajectoryConfig c_;
  bool lemniscate_;
  double omega_ = 0.0;
};

/// @brief Hold a point, optionally rotating in yaw with a ramped rate.
class Hover : public Trajectory {
 public:
  explicit Hover(const TrajectoryConfig& c) : c_(c) {}
  FlatOutput eval(double t) const override {
    FlatOutput o;
    o.p = c_.center;
    o.yaw = c_.yaw0;
    if (c_.yaw_mode == YawMode::kRate) {
      const auto ph = ramp_phase(t - c_.start_delay_s, c_.ramp_s);
      o.yaw += c_.yaw_rate * ph[0];
      o.yaw_rate = c_.yaw_rate * ph[1];
      o.yaw_acc = c_.yaw_rate * ph[2];
    }
    return o;
  }

 private:
  TrajectoryConfig c_;
};

}  // namespace

std::unique_ptr<Trajectory> make_hover(const TrajectoryConfig& c) { return std::make_unique<Hover>(c); }

std::unique_ptr<Trajectory> make_circle(const TrajectoryConfig& c) {
  return std::make_unique<PhaseCurve>(c, false);
}

std::unique_ptr<Trajectory> make_lemniscate(const TrajectoryConfig& c) {
  if (c.yaw_mode == YawMode::kFollow)
    throw std::invalid_argument("trajectory: yaw 'follow' is only defined for circles");
  return std::make_unique<PhaseCurve>(c, true);
}

}  // namespace vid::sim::detail
