/// @file run_simulator.cpp
/// @brief Closed loop of one study run: measure (noisy) -> MPC (nominal mass) -> true dynamics.
#include "massid/gen/run_simulator.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "dynamics/rk4.h"
#include "geometry/so3.h"
#include "massid/gen/mass_profile.h"
#include "massid/gen/mpc_controller.h"
#include "massid/gen/reference_trajectory.h"
#include "massid/gen/rng.h"

namespace vid::massid::gen {
namespace {

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

/// Position and velocity of the vehicle, and their time derivative (same type: a vector space).
struct Translation {
  Eigen::Vector3d p, v;
};
Translation operator+(const Translation& a, const Translation& b) { return {a.p + b.p, a.v + b.v}; }
Translation operator*(double s, const Translation& d) { return {s * d.p, s * d.v}; }

/// p' = v, v' = R(s) (T/m(s)) e3 + g over the sample interval with R(s) = R0 Exp(w (s - tk)),
/// integrated by dynamics::rk4_step.
struct TranslationalModel {
  Eigen::Matrix3d R_WI_k;  ///< attitude at the start of the sample interval t_k
  Eigen::Vector3d w_I;
  double thrust_N;
  double t_k, t_k_end;     ///< sample interval (mass is sampled inside it, see below)
  Eigen::Vector3d g_W;
  const MassProfile* mass;

  Eigen::Vector3d accel(double s) const {
    const Eigen::Matrix3d R = R_WI_k * so3::quat_exp(w_I * (s - t_k)).toRotationMatrix();
    // Steps are on the sample grid and right-continuous: sample the mass inside the interval
    // so a step at t_{k+1} does not leak into [t_k, t_{k+1}).
    const double m = mass->mass_kg(std::min(s, t_k_end - 1e-9 * (t_k_end - t_k)));
    return R.col(2) * (thrust_N / m) + g_W;
  }
  void step(double t0, double h, Eigen::Vector3d* p, Eigen::Vector3d* v) const {
    auto f = [this](double s, const Translation& x) { return Translation{x.v, accel(s)}; };
    // One expression per member, x + k d, as the step this replaced (same roundings).
    auto add_scaled = [](const Translation& x, const Translation& d, double k) {
      return Translation{x.p + k * d.p, x.v + k * d.v};
    };
    const Translation y = dynamics::rk4_step<Translation>(t0, h, Translation{*p, *v}, f, add_scaled);
    *p = y.p;
    *v = y.v;
  }
};

}  // namespace

std::uint64_t run_seed(std::uint64_t base_seed, const std::string& trajectory,
                       const std::string& profile, int index) {
  std::uint64_t h = mix_seed(base_seed);
  h = mix_seed(h ^ fnv1a(trajectory));
  h = mix_seed(h ^ fnv1a(profile));
  return mix_seed(h ^ static_cast<std::uint64_t>(index));
}

SimulatedRun simulate_run(const GeneratorSettings& s, const std::string& trajectory,
                          const std::string& profile, int index, std::uint64_t seed) {
  Rng param_rng(seed ^ 0x7061'7261'6D73ull);
  const double m_base = param_rng.uniform(s.mass_min_kg, s.mass_max_kg);
  const MassProfile mass = MassProfile::make(profile, m_base, s.mass, s.rate_hz, seed);
  const auto reference = make_reference_trajectory(trajectory, s.trajectory, seed);
  const double m_nominal = s.initial_mass_factor * mass.mass_kg(0.0);
  const double weight = m_base * s.gravity;
  const double thrust_lo = s.controller.thrust_min_ratio * weight;
  const double thrust_hi = s.controller.thrust_max_ratio * weight;
  const double dt = 1.0 / s.rate_hz;
  MpcController controller(s.controller, m_nominal, s.gravity, thrust_lo, thrust_hi, dt);
  Rng noise(seed ^ 0x6E6F'6973'65ull);

  SimulatedRun out;
  RunInfo& info = out.run.info;
  info.trajectory = trajectory;
  info.mass_profile = profile;
  info.index = index;
  info.seed = seed;
  info.gravity = s.gravity;
  info.initial_mass_guess = m_nominal;
  info.sigma_q = s.sigma_q;
  info.sigma_p = s.sigma_p;
  info.sigma_v = s.sigma_v;
  out.stats.mass_base_kg = m_base;
  out.stats.thrust_bound_min_N = thrust_lo;
  out.stats.thrust_bound_max_N = thrust_hi;
  out.stats.thrust_min_N = INFINITY;
  out.stats.thrust_max_N = -INFINITY;

  // Start in hover at the reference's start, level, heading zero.
  Eigen::Quaterniond q_WI = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_WI = reference->at(0.0).p_W;
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  const Eigen::Vector3d g_W(0, 0, -s.gravity);

  const long n = std::lround(s.duration_s * s.rate_hz) + 1;
  out.run.samples.reserve(n);
  out.truth.reserve(n);
  double sq_err = 0.0;
  long saturated = 0;
  for (long k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / s.rate_hz;
    RunTruthSample truth;
    truth.T_WI = {q_WI, p_WI};
    truth.v_WI = v_WI;
    truth.p_ref_W = reference->at(t).p_W;
    sq_err += (p_WI - truth.p_ref_W).squaredNorm();

    MassIdSample sample;
    sample.t = t;
    // q noise is a local (right) perturbation: q_meas = q ⊗ exp(n_q / 2).
    sample.q_WI = (q_WI * so3::quat_exp(noise.normal3(s.sigma_q))).normalized();
    sample.p_WI = p_WI + noise.normal3(s.sigma_p);
    sample.v_WI = v_WI + noise.normal3(s.sigma_v);
    const ControlOutput u = controller.compute(t, sample.q_WI, sample.p_WI, sample.v_WI, *reference);
    sample.thrust_cmd = u.thrust_N;
    sample.w_I = u.w_I;
    sample.mass_true = mass.mass_kg(t);
    if (u.saturated) ++saturated;
    truth.a_cmd_W = u.a_cmd_W;
    truth.saturated = u.saturated;
    out.stats.thrust_min_N = std::min(out.stats.thrust_min_N, u.thrust_N);
    out.stats.thrust_max_N = std::max(out.stats.thrust_max_N, u.thrust_N);
    out.run.samples.push_back(sample);
    out.truth.push_back(truth);

    // True dynamics over [t_k, t_{k+1}) with the held commands.
    const double t_next = static_cast<double>(k + 1) / s.rate_hz;
    TranslationalModel model{q_WI.toRotationMatrix(), u.w_I, u.thrust_N, t, t_next, g_W, &mass};
    const double h = (t_next - t) / s.integration_substeps;
    for (int i = 0; i < s.integration_substeps; ++i) model.step(t + i * h, h, &p_WI, &v_WI);
    q_WI = (q_WI * so3::quat_exp(u.w_I * (t_next - t))).normalized();
  }
  out.stats.position_rmse_m = std::sqrt(sq_err / static_cast<double>(n));
  out.stats.saturated_fraction = static_cast<double>(saturated) / static_cast<double>(n);
  return out;
}

void write_truth_csv(const std::filesystem::path& file, const SimulatedRun& run) {
  std::string text =
      "t,px,py,pz,qw,qx,qy,qz,vx,vy,vz,px_ref,py_ref,pz_ref,ax_cmd,ay_cmd,az_cmd,saturated\n";
  auto add = [&text](double x) {
    char buf[64];
    text.append(buf, std::to_chars(buf, buf + sizeof(buf), x).ptr);
    text += ',';
  };
  for (size_t k = 0; k < run.truth.size(); ++k) {
    const RunTruthSample& x = run.truth[k];
    add(run.run.samples[k].t);
    for (int i = 0; i < 3; ++i) add(x.T_WI.p[i]);
    add(x.T_WI.q.w());
    for (int i = 0; i < 3; ++i) add(x.T_WI.q.vec()[i]);
    for (int i = 0; i < 3; ++i) add(x.v_WI[i]);
    for (int i = 0; i < 3; ++i) add(x.p_ref_W[i]);
    for (int i = 0; i < 3; ++i) add(x.a_cmd_W[i]);
    text += x.saturated ? "1\n" : "0\n";
  }
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  out << text;
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

}  // namespace vid::massid::gen
