/// @file force_sources.cpp
/// @brief Force sources with analytic rates (see force_sources.h).

#include "sim/force_sources.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/csv_reader.h"
#include "sim/render/random.h"

namespace vid::sim {

ForceTable load_force_table(const std::filesystem::path& csv) {
  io::CsvReader in(csv);
  ForceTable table;
  table.file = csv.string();
  while (in.next_row()) {
    in.expect_columns(4);
    const double t = static_cast<double>(in.get_int(0, "t_ns")) * 1e-9;
    if (!table.t_s.empty() && !(t > table.t_s.back())) {
      in.fail("column 1 't_ns': times must be strictly increasing (" + std::string(in.field(0)) +
              " after " + std::to_string(std::llround(table.t_s.back() * 1e9)) + ")");
    }
    table.t_s.push_back(t);
    table.f_W_N.emplace_back(in.get_double(1, "Fx [N]"), in.get_double(2, "Fy [N]"), in.get_double(3, "Fz [N]"));
  }
  if (table.empty()) throw io::DatasetError(csv.string() + ": no data rows (expected t_ns, Fx, Fy, Fz)");
  return table;
}

ForceAndRate ForceTable::eval(double t) const {
  ForceAndRate out;
  if (t_s.empty()) return out;
  if (t <= t_s.front()) {
    out.f_W = f_W_N.front();
    return out;
  }
  if (t >= t_s.back()) {
    out.f_W = f_W_N.back();
    return out;
  }
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(t_s.begin(), t_s.end(), t) - t_s.begin()) - 1;
  const double h = t_s[i + 1] - t_s[i];
  const double a = (t - t_s[i]) / h;
  out.f_W = (1.0 - a) * f_W_N[i] + a * f_W_N[i + 1];
  out.df_W = (f_W_N[i + 1] - f_W_N[i]) / h;
  return out;
}

ForceAndRate rope_force(const RopeConfig& r, const Eigen::Vector3d& p_W, const Eigen::Vector3d& v_W,
                        const Eigen::Vector3d& a_W) {
  ForceAndRate out;
  const Eigen::Vector3d d = p_W - r.anchor_W;
  const double len = d.norm();
  const double stretch = len - r.rest_length_m;
  if (!r.enabled || stretch <= 0.0 || len < 1e-9) return out;
  const Eigen::Vector3d u = d / len;
  const double rate = u.dot(v_W);                                   // d(stretch)/dt
  const double rate2 = u.dot(a_W) + (v_W.squaredNorm() - rate * rate) / len;  // d2(stretch)/dt2
  const bool fading = r.damping_ramp_m > 0.0 && stretch < r.damping_ramp_m;
  const double fade = fading ? stretch / r.damping_ramp_m : 1.0;
  const double dfade = fading ? rate / r.damping_ramp_m : 0.0;
  const double c = r.damping_Ns_per_m;
  const double tension = r.stiffness_N_per_m * stretch + fade * c * rate;
  if (tension <= 0.0) return out;  // a fast retraction would make the damper push: a rope cannot
  const double dtension = r.stiffness_N_per_m * rate + dfade * c * rate + fade * c * rate2;
  const Eigen::Vector3d du = (v_W - rate * u) / len;
  out.f_W = -tension * u;
  out.df_W = -dtension * u - tension * du;
  return out;
}

ForceAndRate pulse_force(const PushConfig& p, double t) {
  ForceAndRate out;
  const double u = (t - p.t_s) / p.duration_s;
  if (u > 0.0 && u < 1.0) {
    const double s = std::sin(M_PI * u);
    out.f_W = p.force_N * s * s;
    out.df_W = p.force_N * (M_PI / p.duration_s) * std::sin(2.0 * M_PI * u);  // d/dt sin^2 = pi/D sin(2 pi u)
  }
  return out;
}

Eigen::Vector2d step_fraction(const ForceStepConfig& s, double t) {
  if (s.rise_s <= 0.0) return Eigen::Vector2d(t >= s.t_s ? 1.0 : 0.0, 0.0);
  const double u = (t - s.t_s) / s.rise_s;
  if (u <= 0.0) return Eigen::Vector2d::Zero();
  if (u >= 1.0) return Eigen::Vector2d(1.0, 0.0);
  return Eigen::Vector2d(u, 1.0 / s.rise_s);
}

std::vector<PushConfig> draw_random_impacts(const RandomImpactsConfig& c, double duration_s, std::uint64_t seed) {
  std::vector<PushConfig> out;
  if (!(c.rate_per_s > 0.0)) return out;
  Rng rng(seed);
  const double end = c.end_s < 0.0 ? duration_s : std::min(c.end_s, duration_s);
  double t = c.start_s;
  while (true) {
    t += -std::log(1.0 - rng.uniform()) / c.rate_per_s;  // exponential inter-arrival times
    PushConfig p;
    p.t_s = t;
    p.duration_s = rng.uniform(c.duration_min_s, c.duration_max_s);
    const double peak = rng.uniform(c.peak_min_N, c.peak_max_N);
    // Direction: every draw is made whatever the mode, so the times do not depend on it.
    const double az = rng.uniform(0.0, 2.0 * M_PI);
    const double cz = rng.uniform(-1.0, 1.0);
    Eigen::Vector3d dir;
    if (c.directions == "up") {
      dir = Eigen::Vector3d::UnitZ();
    } else if (c.directions == "any") {
      const double sz = std::sqrt(1.0 - cz * cz);
      dir = Eigen::Vector3d(sz * std::cos(az), sz * std::sin(az), cz);
    } else {
      dir = Eigen::Vector3d(std::cos(az), std::sin(az), 0.0);
    }
    if (t + p.duration_s > end) break;
    p.force_N = peak * dir;
    out.push_back(p);
  }
  return out;
}

}  // namespace vid::sim
