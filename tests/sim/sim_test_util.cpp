#include "sim_test_util.h"

#include <cmath>
#include <sstream>

namespace vid::sim::test {

std::string preset_path(const std::string& name) { return std::string(VID_SOURCE_DIR) + "/config/sim/" + name + ".yaml"; }

Scenario hover_scenario(const std::string& extra, double duration_s, double imu_rate_hz) {
  std::ostringstream yaml;
  yaml << "name: fault_hover\nseed: 11\nnoise: true\nduration_s: " << duration_s << R"(
vehicle:
  mass_kg: 3.1015
  inertia_diag: [0.0347, 0.0458, 0.0977]
  arm_length_m: 0.325
  thrust_coefficients: [2.6890e-7, 2.8190e-7, 2.7263e-7, 2.7741e-7]
  motor_time_constant_s: 0.03
  rotor_speed_min: 1000
  rotor_speed_max: 9000
trajectory: {type: hover, center: [0, 0, 1.2]}
rotor_sensor: {rate_hz: 100, noise_density: 0}
imu:
  gyroscope_noise_density: 0
  gyroscope_random_walk: 0
  accelerometer_noise_density: 0
  accelerometer_random_walk: 0
  rate_hz: )" << imu_rate_hz << "\n";
  // Top-level keys of extra replace the base's.
  YAML::Node root = YAML::Load(yaml.str());
  const YAML::Node over = YAML::Load(extra);
  if (over.IsMap())
    for (const auto& kv : over) root[kv.first.Scalar()] = kv.second;
  YAML::Emitter out;
  out << root;
  return load_scenario_string(out.c_str(), "fault_hover.yaml");
}

Recording record(Scenario sc) {
  sc.cameras.cameras.clear();
  Simulator sim(sc);
  Recording rec;
  sim.run(rec);
  return rec;
}

double tracking_rmse(const Simulator& sim, const Recording& rec, double t_from_s) {
  double sum = 0.0;
  int n = 0;
  for (const GroundTruthSample& g : rec.gt) {
    const double t = static_cast<double>(g.t_ns - sim.scenario().start_time_ns) * 1e-9;
    if (t < t_from_s) continue;
    sum += (g.T_WI.p - sim.trajectory().eval(t).p).squaredNorm();
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : INFINITY;
}

}  // namespace vid::sim::test
