/// @file from_sequence.cpp
/// @brief A VID sequence folder as one study run (see from_sequence.h).
#include "massid/gen/from_sequence.h"

#include <algorithm>
#include <cmath>
#include <variant>
#include <vector>

#include "geometry/so3.h"
#include "io/dataset_reader.h"
#include "io/errors.h"
#include "massid/gen/rng.h"
#include "vio_core/thrust.h"

namespace vid::massid::gen {
namespace {

struct Streams {
  std::vector<GroundTruthSample> gt;
  std::vector<RotorSample> rotors;
  std::vector<MassSample> mass;
};

/// Index i with t[i] <= t < t[i+1] (t inside the samples' span).
template <class V>
std::size_t bracket(const V& v, TimeNs t) {
  const auto it = std::upper_bound(v.begin(), v.end(), t,
                                   [](TimeNs x, const auto& s) { return x < s.t_ns; });
  return static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - v.begin()) - 1));
}

GroundTruthSample gt_at(const std::vector<GroundTruthSample>& gt, TimeNs t) {
  const std::size_t i = bracket(gt, t);
  if (i + 1 >= gt.size()) return gt.back();
  const GroundTruthSample& a = gt[i];
  const GroundTruthSample& b = gt[i + 1];
  const double u = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  GroundTruthSample s = a;
  s.t_ns = t;
  s.T_WI.p = a.T_WI.p + u * (b.T_WI.p - a.T_WI.p);
  s.T_WI.q = so3::boxplus(a.T_WI.q, u * so3::boxminus(b.T_WI.q, a.T_WI.q));
  s.v_WI = a.v_WI + u * (b.v_WI - a.v_WI);
  return s;
}

double mass_at(const std::vector<MassSample>& m, TimeNs t) {
  const std::size_t i = bracket(m, t);
  if (i + 1 >= m.size()) return m.back().mass_kg;
  const double u = static_cast<double>(t - m[i].t_ns) / static_cast<double>(m[i + 1].t_ns - m[i].t_ns);
  return m[i].mass_kg + u * (m[i + 1].mass_kg - m[i].mass_kg);
}

}  // namespace

SequenceRun run_from_sequence(const std::filesystem::path& sequence, const std::string& name,
                              const FromSequenceSettings& s) {
  io::ReaderOptions options;
  options.read_images = false;
  options.read_features = false;
  io::DatasetReader reader(sequence, options);
  const io::DatasetCalibration& calib = reader.calibration();
  if (!calib.vehicle || calib.vehicle->rotor_thrust_coefficients.empty()) {
    throw io::DatasetError(sequence.string() + ": needs vehicle.yaml with thrust coefficients");
  }
  Streams in;
  while (auto m = reader.next()) {
    if (auto* g = std::get_if<GroundTruthSample>(&*m)) in.gt.push_back(*g);
    else if (auto* r = std::get_if<RotorSample>(&*m)) in.rotors.push_back(*r);
    else if (auto* ms = std::get_if<MassSample>(&*m)) in.mass.push_back(*ms);
  }
  for (const auto& [stream, n] : {std::pair{"state_groundtruth_estimate0", in.gt.size()},
                                  std::pair{"rotor0", in.rotors.size()},
                                  std::pair{"mass0", in.mass.size()}}) {
    if (n < 2) throw io::DatasetError(sequence.string() + ": needs " + stream + " (found " + std::to_string(n) + " rows)");
  }
  const TimeNs t0 = std::max({in.gt.front().t_ns, in.rotors.front().t_ns, in.mass.front().t_ns});
  const TimeNs t_end = std::min({in.gt.back().t_ns, in.rotors.back().t_ns, in.mass.back().t_ns});
  const double dt = 1.0 / s.rate_hz;
  const auto step_ns = static_cast<TimeNs>(std::llround(dt * 1e9));
  if (t_end - t0 < 2 * step_ns) {
    throw io::DatasetError(sequence.string() + ": ground truth, rotor0 and mass0 overlap for less than two samples");
  }
  const long n = static_cast<long>((t_end - t0) / step_ns);  // the last sample keeps its interval inside the span

  SequenceRun out;
  out.t0_ns = t0;
  RunInfo& info = out.run.info;
  info.trajectory = name;
  info.mass_profile = "sequence";
  info.seed = s.seed;
  info.gravity = calib.vehicle->gravity;
  info.initial_mass_guess = s.initial_mass_factor * calib.vehicle->mass_kg;
  info.sigma_q = s.sigma_q;
  info.sigma_p = s.sigma_p;
  info.sigma_v = s.sigma_v;

  Rng noise(s.seed);
  out.run.samples.reserve(static_cast<std::size_t>(n));
  GroundTruthSample next = gt_at(in.gt, t0);
  for (long k = 0; k < n; ++k) {
    const TimeNs t = t0 + k * step_ns;
    const GroundTruthSample now = next;
    next = gt_at(in.gt, t + step_ns);
    MassIdSample sample;
    sample.t = static_cast<double>(k) * dt;
    sample.q_WI = (now.T_WI.q * so3::quat_exp(noise.normal3(s.sigma_q))).normalized();
    sample.p_WI = now.T_WI.p + noise.normal3(s.sigma_p);
    sample.v_WI = now.v_WI + noise.normal3(s.sigma_v);
    sample.w_I = so3::boxminus(next.T_WI.q, now.T_WI.q) / dt;
    double thrust_sum = 0.0;
    int count = 0;
    for (std::size_t i = bracket(in.rotors, t); i < in.rotors.size() && in.rotors[i].t_ns < t + step_ns; ++i) {
      if (in.rotors[i].t_ns < t) continue;
      thrust_sum += collective_thrust(in.rotors[i], *calib.vehicle);
      ++count;
    }
    sample.thrust_cmd = count > 0 ? thrust_sum / count
                                  : collective_thrust(in.rotors[bracket(in.rotors, t)], *calib.vehicle);
    sample.mass_true = mass_at(in.mass, t);
    out.run.samples.push_back(sample);
  }
  return out;
}

}  // namespace vid::massid::gen
