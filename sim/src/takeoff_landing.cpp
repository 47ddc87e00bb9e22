/// @file takeoff_landing.cpp
/// @brief Timeline, reference trajectory and pilot of flights that start and end on the
/// ground (takeoff_landing.h has the timeline).

#include "sim/takeoff_landing.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "smooth_profile.h"

namespace vid::sim {

namespace {

/// Between the planned touchdown and the planned landing detection: the actual touchdown
/// follows the reference with the controller's lag.
constexpr double kTouchdownMarginS = 0.5;
/// The descent reference stops over this time after the planned touchdown (ends
/// descent_speed * kDescentStopS / 2 below the resting height).
constexpr double kDescentStopS = 0.4;

double yaw_of(const Eigen::Quaterniond& q_WI) {
  const Eigen::Matrix3d R = q_WI.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}

/// @brief Rest-to-rest smoothstep from p0 (at t0) to p1 (at t0 + T), heading held.
FlatOutput smoothstep_move(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double t0, double T, double t,
                           double yaw) {
  const auto S = detail::smoothstep7((t - t0) / T);
  const Eigen::Vector3d d = p1 - p0;
  FlatOutput o;
  o.p = p0 + d * S[0];
  o.v = d * S[1] / T;
  o.a = d * S[2] / (T * T);
  o.j = d * S[3] / (T * T * T);
  o.s = d * S[4] / (T * T * T * T);
  o.yaw = yaw;
  return o;
}

/// @brief f(tau(t)) from f's derivatives at tau and tau's time derivatives th[1..4]
/// (Faa di Bruno up to the fourth order).
FlatOutput time_warp(const FlatOutput& f, const std::array<double, 5>& th) {
  const double t1 = th[1], t2 = th[2], t3 = th[3], t4 = th[4];
  FlatOutput o;
  o.p = f.p;
  o.v = f.v * t1;
  o.a = f.a * t1 * t1 + f.v * t2;
  o.j = f.j * t1 * t1 * t1 + 3.0 * f.a * t1 * t2 + f.v * t3;
  o.s = f.s * t1 * t1 * t1 * t1 + 6.0 * f.j * t1 * t1 * t2 + 3.0 * f.a * t2 * t2 + 4.0 * f.a * t1 * t3 + f.v * t4;
  o.yaw = f.yaw;
  o.yaw_rate = f.yaw_rate * t1;
  o.yaw_acc = f.yaw_acc * t1 * t1 + f.yaw_rate * t2;
  return o;
}

/// @brief Phase tau of the slow-down: tau' falls smoothly 1 -> 0 over [0, T] (tau = s - phi).
std::array<double, 5> slow_down_phase(double s, double T) {
  const auto ph = detail::ramp_phase(s, T);
  return {s - ph[0], 1.0 - ph[1], -ph[2], -ph[3], -ph[4]};
}

/// Spin-up thrust limit at its end, as a multiple of the weight.
constexpr double kSpinUpLimitFactor = 1.25;

/// @brief Duration of the smooth speed ramps (0 -> v) of climb and descent: half the
/// acceleration limit at the ramp's peak (ramp_phase: peak phi'' = S'max / T), >= 0.5 s.
double speed_ramp_s(double speed, double max_accel) {
  return std::max(0.5, 2.0 * detail::kSmoothstepPeakVel * speed / max_accel);
}

/// @brief Vertical move at cruise speed v with smooth speed ramps of length T_r: starts at
/// t0, covers @p height (v ramps up over [t0, t0 + T_r], down over [t1, t1 + T_r] with
/// t1 = t0 + height / v). Returns z offset and its four derivatives.
std::array<double, 5> cruise_profile(double t, double t0, double height, double v, double T_r) {
  const auto a = detail::ramp_phase(t - t0, T_r);
  const auto b = detail::ramp_phase(t - t0 - height / v, T_r);
  return {v * (a[0] - b[0]), v * (a[1] - b[1]), v * (a[2] - b[2]), v * (a[3] - b[3]), v * (a[4] - b[4])};
}

FlatOutput vertical(const Eigen::Vector3d& p0, const std::array<double, 5>& dz, double sign, double yaw) {
  FlatOutput o;
  o.p = p0;
  o.p.z() += sign * dz[0];
  o.v.z() = sign * dz[1];
  o.a.z() = sign * dz[2];
  o.j.z() = sign * dz[3];
  o.s.z() = sign * dz[4];
  o.yaw = yaw;
  return o;
}

double slow_down_s(double max_speed, double max_accel) {
  // Slowing down adds v tau'' (peak v S'max / T) to the path's own acceleration: half the limit.
  return std::max(1.0, 2.0 * detail::kSmoothstepPeakVel * max_speed / max_accel);
}

class TakeoffLandingTrajectory : public Trajectory {
 public:
  TakeoffLandingTrajectory(std::unique_ptr<Trajectory> flight, const TakeoffLandingPlan& plan,
                           const TakeoffLandingConfig& config, double max_accel)
      : flight_(std::move(flight)), plan_(plan), v_c_(config.climb_speed_mps), v_d_(config.descent_speed_mps),
        ramp_c_(speed_ramp_s(config.climb_speed_mps, max_accel)),
        ramp_d_(speed_ramp_s(config.descent_speed_mps, max_accel)) {
    const FlatOutput stop = flight_->eval(stop_tau());
    p_stop_W_ = stop.p;
    yaw_stop_ = stop.yaw;
  }

  FlatOutput eval(double t) const override {
    const TakeoffLandingPlan& P = plan_;
    FlatOutput o;
    if (t < P.climbed_s) {  // at rest until spin_up, then the climb
      const double height = P.p_hover_W.z() - P.p_rest_W.z();
      o = vertical(P.p_rest_W, cruise_profile(t, P.spin_up_s, height, v_c_, ramp_c_), 1.0, P.yaw_start);
    } else if (t < P.flight_s) {
      o.p = P.p_hover_W;
      o.yaw = P.yaw_start;
    } else if (t < P.stop_s) {
      o = flight_->eval(t - P.flight_s);
    } else if (t < P.return_s) {
      auto th = slow_down_phase(t - P.stop_s, P.return_s - P.stop_s);
      th[0] += P.stop_s - P.flight_s;
      o = time_warp(flight_->eval(th[0]), th);
    } else if (t < P.hover_s) {
      o = smoothstep_move(p_stop_W_, P.p_hover_W, P.return_s, P.hover_s - P.return_s, t, yaw_stop_);
    } else {
      // Hover, then descend at v_d from `descent`, stopping kDescentStopS after `touchdown`.
      const auto a = detail::ramp_phase(t - P.descent_s, ramp_d_);
      const auto b = detail::ramp_phase(t - P.touchdown_s, kDescentStopS);
      const std::array<double, 5> dz = {v_d_ * (a[0] - b[0]), v_d_ * (a[1] - b[1]), v_d_ * (a[2] - b[2]),
                                        v_d_ * (a[3] - b[3]), v_d_ * (a[4] - b[4])};
      o = vertical(P.p_hover_W, dz, -1.0, yaw_stop_);
    }
    return o;
  }

  double duration_s() const override { return plan_.disarm_s; }

 private:
  double stop_tau() const { return plan_.stop_s - plan_.flight_s + 0.5 * (plan_.return_s - plan_.stop_s); }

  std::unique_ptr<Trajectory> flight_;
  TakeoffLandingPlan plan_;
  double v_c_, v_d_, ramp_c_, ramp_d_;
  Eigen::Vector3d p_stop_W_;
  double yaw_stop_ = 0.0;
};

}  // namespace

TakeoffLandingPlan plan_takeoff_landing(const TakeoffLandingConfig& c, const Trajectory& flight, double rest_height_m,
                                        double duration_s, double max_speed, double max_accel,
                                        double motor_time_constant_s) {
  TakeoffLandingPlan P;
  const FlatOutput f0 = flight.eval(0.0);
  const double climb_m = f0.p.z() - rest_height_m;
  if (!(climb_m >= 0.1))
    throw std::invalid_argument("takeoff_landing: the trajectory must start >= 0.1 m above the resting height " +
                                std::to_string(rest_height_m) + " m (starts at z = " + std::to_string(f0.p.z()) + ")");
  if (f0.v.norm() > 1e-9 || f0.a.norm() > 1e-9)
    throw std::invalid_argument("takeoff_landing: the trajectory must start at rest (its t = 0 follows the climb)");
  P.p_hover_W = f0.p;
  P.p_rest_W = Eigen::Vector3d(f0.p.x(), f0.p.y(), rest_height_m);
  P.yaw_start = f0.yaw;
  // Forward from the start.
  P.arm_s = c.rest_start_s;
  P.spin_up_s = P.arm_s + c.idle_s;
  P.spin_up_end_s = P.spin_up_s + c.spin_up_s;
  P.climbed_s = P.spin_up_s + climb_m / c.climb_speed_mps + speed_ramp_s(c.climb_speed_mps, max_accel);
  P.flight_s = P.climbed_s + c.hover_s;
  // Backward from the end: rotors run down (first-order lag to 2 % of idle) before rest_end_s.
  const double run_down_s = motor_time_constant_s * std::log(1.0 / kRotorStopFraction) + 0.05;
  P.disarm_s = duration_s - c.rest_end_s - run_down_s;
  const double landed_s = P.disarm_s - c.idle_s - c.spin_down_s;
  P.touchdown_s = landed_s - c.land_detect_s - kTouchdownMarginS;
  P.descent_s = P.touchdown_s - 0.5 * speed_ramp_s(c.descent_speed_mps, max_accel) - climb_m / c.descent_speed_mps;
  P.hover_s = P.descent_s - c.hover_s;
  // Slow down, then return above the take-off spot; the return's length depends on where the
  // flight stops, which depends on the return's duration: iterate (it only grows).
  const double T_stop = slow_down_s(max_speed, max_accel);
  double T_return = 1.0;
  for (int it = 0; it < 20; ++it) {
    const double stop_s = P.hover_s - T_return - T_stop;
    const Eigen::Vector3d p_stop = flight.eval(stop_s - P.flight_s + 0.5 * T_stop).p;
    const double need = std::max(1.0, detail::smoothstep_duration((P.p_hover_W - p_stop).norm(), max_speed, max_accel));
    if (need <= T_return) break;
    T_return = need;
  }
  P.return_s = P.hover_s - T_return;
  P.stop_s = P.return_s - T_stop;
  if (!(P.stop_s > P.flight_s)) {
    const double needed = duration_s + (P.flight_s - P.stop_s);
    throw std::invalid_argument("takeoff_landing: duration_s " + std::to_string(duration_s) +
                                " s leaves no time for the trajectory between take-off and landing (needs > " +
                                std::to_string(needed) + " s)");
  }
  return P;
}

std::unique_ptr<Trajectory> make_takeoff_landing_trajectory(std::unique_ptr<Trajectory> flight,
                                                            const TakeoffLandingPlan& plan,
                                                            const TakeoffLandingConfig& config, double max_accel) {
  return std::make_unique<TakeoffLandingTrajectory>(std::move(flight), plan, config, max_accel);
}

TakeoffLandingPilot::TakeoffLandingPilot(const TakeoffLandingConfig& config, const TakeoffLandingPlan& plan,
                                         const dynamics::QuadrotorModel& armed_model)
    : config_(config), plan_(plan), model_(armed_model) {
  const double idle = model_.params().rotor_speed_min;
  idle_thrust_N_ = model_.rotor_thrusts(Eigen::VectorXd::Constant(model_.rotor_count(), idle)).sum();
}

Eigen::VectorXd TakeoffLandingPilot::command(const ControllerInput& in, GeometricController& ctrl,
                                             const Trajectory& ref, double dt_s, double weight_N) {
  const double t = in.t_s;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model_.rotor_count());
  const Eigen::VectorXd idle = Eigen::VectorXd::Constant(model_.rotor_count(), model_.params().rotor_speed_min);
  disarmed_ = false;
  if (t < plan_.arm_s) {
    disarmed_ = true;
    return zero;
  }
  if (t < plan_.spin_up_s) return idle;
  if (!landed_s_) {
    if (!tracking_) {
      ctrl.reset(Eigen::Vector3d::Zero());  // nothing to hold against yet: the ground carried the weight
      tracking_ = true;
    }
    ControllerInput limited = in;
    if (t < plan_.spin_up_end_s) {
      const double u = (t - plan_.spin_up_s) / (plan_.spin_up_end_s - plan_.spin_up_s);
      limited.max_thrust_N = idle_thrust_N_ + (kSpinUpLimitFactor * weight_N - idle_thrust_N_) * u;
    }
    if (t >= plan_.descent_s && in.in_contact) {
      if (!contact_since_s_) contact_since_s_ = t;
    } else {
      contact_since_s_.reset();
    }
    if (contact_since_s_ && t - *contact_since_s_ >= config_.land_detect_s - 1e-9) {
      landed_s_ = t;
      landed_thrust_N_ = model_.rotor_thrusts(in.state.rotor_speeds).sum();
      landed_yaw_ = yaw_of(in.state.q_WI);
    } else {
      if (t >= plan_.disarm_s)
        throw std::runtime_error("takeoff_landing: the vehicle has not landed by the disarm time " +
                                 std::to_string(plan_.disarm_s) + " s");
      return ctrl.update(limited, ref, dt_s);
    }
  }
  const double u = (t - *landed_s_) / config_.spin_down_s;
  if (u < 1.0) {
    return ctrl.attitude_hold(in.state, landed_thrust_N_ * (1.0 - detail::smoothstep7(u)[0]), landed_yaw_);
  }
  if (t < std::max(plan_.disarm_s, *landed_s_ + config_.spin_down_s + config_.idle_s)) return idle;
  disarmed_ = true;
  return zero;
}

}  // namespace vid::sim
