/// @file mini_sim.cpp
/// @brief Deterministic loop-trajectory simulation for the filter tests.
#include "mini_sim.h"

#include <cmath>
#include <random>

#include "dynamics/rk4.h"
#include "geometry/so3.h"

namespace vid::massid::test {
namespace {

constexpr double kGravity = 9.81;

struct Truth {
  Eigen::Quaterniond q_WI;
  Eigen::Vector3d p_WI, v_WI;
};

/// Reference position, acceleration of the loop (circle with a vertical wave).
void reference(const MiniSimConfig& c, double t, Eigen::Vector3d* p, Eigen::Vector3d* a) {
  const double w = 2.0 * M_PI / c.loop_period_s, r = c.loop_radius_m, h = c.loop_height_amp_m;
  *p = Eigen::Vector3d(r * std::cos(w * t), r * std::sin(w * t), 1.0 + h * std::sin(2 * w * t));
  *a = Eigen::Vector3d(-r * w * w * std::cos(w * t), -r * w * w * std::sin(w * t),
                       -4.0 * h * w * w * std::sin(2 * w * t));
}

/// Attitude whose z axis is the required specific force, zero yaw.
Eigen::Matrix3d reference_attitude(const MiniSimConfig& c, double t, double* f_norm) {
  Eigen::Vector3d p, a;
  reference(c, t, &p, &a);
  const Eigen::Vector3d f = a + Eigen::Vector3d(0, 0, kGravity);
  *f_norm = f.norm();
  const Eigen::Vector3d z = f / f.norm();
  const Eigen::Vector3d y = z.cross(Eigen::Vector3d::UnitX()).normalized();
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Matrix3d R;
  R << x, y, z;
  return R;
}

/// Derivative of a Truth (quaternion as its 4 coefficients).
struct TruthDot {
  Eigen::Vector4d dq;
  Eigen::Vector3d dp, dv;
};
TruthDot operator+(const TruthDot& a, const TruthDot& b) { return {a.dq + b.dq, a.dp + b.dp, a.dv + b.dv}; }
TruthDot operator*(double k, const TruthDot& d) { return {k * d.dq, k * d.dp, k * d.dv}; }

/// Continuous eq. 47 derivative for RK4.
TruthDot derivative(const Truth& s, double T, const Eigen::Vector3d& w, double m) {
  const Eigen::Quaterniond qd = s.q_WI * Eigen::Quaterniond(0.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z());
  return {qd.coeffs(), s.v_WI, s.q_WI * Eigen::Vector3d(0, 0, T / m) + Eigen::Vector3d(0, 0, -kGravity)};
}

Truth add(const Truth& s, const TruthDot& d, double h) {
  Truth o;
  o.q_WI.coeffs() = s.q_WI.coeffs() + h * d.dq;
  o.p_WI = s.p_WI + h * d.dp;
  o.v_WI = s.v_WI + h * d.dv;
  return o;
}

}  // namespace

MassIdRun simulate_loop(const MiniSimConfig& c) {
  MassIdRun run;
  run.info.trajectory = "loop";
  run.info.mass_profile = "test";
  run.info.seed = c.seed;
  run.info.gravity = kGravity;
  run.info.initial_mass_guess = c.initial_mass_guess;
  run.info.sigma_q = c.sigma_q;
  run.info.sigma_p = c.sigma_p;
  run.info.sigma_v = c.sigma_v;
  std::mt19937_64 rng(c.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto noise3 = [&](double s) { return Eigen::Vector3d(s * n01(rng), s * n01(rng), s * n01(rng)); };

  const double dt = 1.0 / c.rate_hz;
  const int n = static_cast<int>(std::lround(c.duration_s * c.rate_hz)) + 1;
  double f0;
  Eigen::Vector3d p0, a0;
  reference(c, 0.0, &p0, &a0);
  Truth x{Eigen::Quaterniond(reference_attitude(c, 0.0, &f0)), p0,
          Eigen::Vector3d(0, 2.0 * M_PI / c.loop_period_s * c.loop_radius_m,
                          2.0 * c.loop_height_amp_m * 2.0 * M_PI / c.loop_period_s)};
  for (int k = 0; k < n; ++k) {
    const double t = k * dt;
    double f_norm, f_next;
    const Eigen::Matrix3d R_now = reference_attitude(c, t, &f_norm);
    const Eigen::Matrix3d R_next = reference_attitude(c, t + dt, &f_next);
    MassIdSample s;
    s.t = t;
    s.mass_true = c.mass(t);
    // Commands: thrust for the true mass (a perfect tracker), body rate taking the
    // reference attitude to the next one over the held interval.
    s.thrust_cmd = s.mass_true * f_norm;
    s.w_I = so3::log(R_now.transpose() * R_next) / dt;
    s.q_WI = so3::boxplus(x.q_WI, noise3(c.sigma_q));
    s.p_WI = x.p_WI + noise3(c.sigma_p);
    s.v_WI = x.v_WI + noise3(c.sigma_v);
    run.samples.push_back(s);
    // Truth: RK4 with 10 sub-steps, inputs held; the attitude is snapped back onto the
    // reference rotation direction only through the commanded rates (no feedback).
    const int sub = 10;
    const double h = dt / sub;
    for (int i = 0; i < sub; ++i) {
      const double m = c.mass(t + i * h);
      auto f = [&](double /*t*/, const Truth& y) { return derivative(y, s.thrust_cmd, s.w_I, m); };
      x = dynamics::rk4_step<TruthDot>(t + i * h, h, x, f, add);
      x.q_WI.normalize();
    }
  }
  return run;
}

}  // namespace vid::massid::test
