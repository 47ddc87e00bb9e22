#pragma once
/// @file synthetic_run.h
/// @brief Physically consistent synthetic runs for the ELM tests and benchmarks: a quadrotor
/// flying a Lissajous figure. At each sample k the thrust and attitude follow from
/// m_k (a_ref(t_k) + g e_z) = T_k z_I; the body rate w_k is the one that turns R_k into
/// R_{k+1} in one interval; the velocity is integrated with the commands held over the
/// interval (zero-order hold, midpoint attitude R_k Exp(w_k dt / 2)), then noise is added.
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <random>

#include "geometry/so3.h"
#include "massid/run_data.h"

namespace vid::massid::elm::testing {

struct SyntheticSpec {
  double duration = 20.0;  ///< [s]
  double rate = 100.0;     ///< [Hz]
  double amplitude = 1.5;  ///< [m]
  double omega = 0.8;      ///< [rad/s]
  double sigma_v = 0.0;    ///< velocity measurement noise [m/s]
  unsigned seed = 1;
  std::function<double(double)> mass = [](double) { return 1.5; };
};

inline MassIdRun make_synthetic_run(const SyntheticSpec& s) {
  MassIdRun run;
  run.info.trajectory = "synthetic";
  run.info.mass_profile = "custom";
  run.info.gravity = 9.81;
  run.info.initial_mass_guess = s.mass(0.0) * 1.2;
  std::mt19937 rng(s.seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const double A = s.amplitude, w = s.omega, dt = 1.0 / s.rate;
  const Eigen::Vector3d g_e(0.0, 0.0, 9.81);
  auto accel = [&](double t) -> Eigen::Vector3d {
    return Eigen::Vector3d(-A * w * w * std::sin(w * t), -2.0 * A * w * w * std::sin(2 * w * t),
                           -0.507 * w * w * std::sin(1.3 * w * t));
  };
  auto thrust_vector = [&](double t) -> Eigen::Vector3d { return s.mass(t) * (accel(t) + g_e); };
  auto attitude = [&](double t) -> Eigen::Quaterniond {
    return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), thrust_vector(t).normalized());
  };
  const int count = static_cast<int>(s.duration * s.rate) + 1;
  Eigen::Vector3d p(0.0, 0.0, 1.0), v(A * w, A * w, 0.39 * w);
  for (int k = 0; k < count; ++k) {
    const double t = k * dt;
    MassIdSample x;
    x.t = t;
    x.q_WI = attitude(t);
    x.w_I = so3::quat_log(x.q_WI.conjugate() * attitude(t + dt)) / dt;
    x.thrust_cmd = thrust_vector(t).norm();
    x.mass_true = s.mass(t);
    x.p_WI = p;
    x.v_WI = v + s.sigma_v * Eigen::Vector3d(n(rng), n(rng), n(rng));
    run.samples.push_back(x);
    // Zero-order-hold step to the next sample.
    const Eigen::Quaterniond half = so3::quat_exp(0.5 * dt * x.w_I);
    const Eigen::Vector3d a = x.thrust_cmd / x.mass_true * ((x.q_WI * half) * Eigen::Vector3d::UnitZ()) - g_e;
    p += dt * v + 0.5 * dt * dt * a;
    v += dt * a;
  }
  return run;
}

}  // namespace vid::massid::elm::testing
