/// @file scenario_faults.cpp
/// @brief `sensor_faults:` section of a scenario (sim/include/sim/sensor_faults.h).

#include <cmath>
#include <string>

#include "scenario_parts.h"

namespace vid::sim::detail {

namespace {

void require_nonnegative(const io::YamlMap& m, const std::string& key, const Eigen::Vector3d& v) {
  if (!(v.minCoeff() >= 0.0)) m.fail(key, "must be >= 0");
}

VibrationBurst parse_burst(const io::YamlMap& b, double imu_rate_hz) {
  VibrationBurst burst;
  burst.t_s = b.get_double("t_s");
  burst.duration_s = b.get_double("duration_s", burst.duration_s);
  burst.accel_rms = b.get_double("accel_rms", burst.accel_rms);
  burst.gyro_rms = b.get_double("gyro_rms", burst.gyro_rms);
  const Eigen::Vector2d band = b.get_vec2("band_hz", Eigen::Vector2d(burst.band_lo_hz, burst.band_hi_hz));
  b.check_unknown();
  burst.band_lo_hz = band[0];
  burst.band_hi_hz = band[1];
  if (!(burst.duration_s > 0.0)) b.fail("duration_s", "must be > 0");
  if (!(burst.accel_rms >= 0.0)) b.fail("accel_rms", "must be >= 0");
  if (!(burst.gyro_rms >= 0.0)) b.fail("gyro_rms", "must be >= 0");
  if (!(band[0] > 0.0 && band[1] > band[0])) b.fail("band_hz", "expected [lo, hi] with 0 < lo < hi");
  if (!(band[1] < 0.5 * imu_rate_hz)) b.fail("band_hz", "upper edge must be below the IMU's Nyquist frequency");
  return burst;
}

void parse_vibration(const io::YamlMap& v, double imu_rate_hz, VibrationConfig* c) {
  c->enabled = true;
  c->reference_speed = v.get_double("reference_speed", c->reference_speed);
  c->speed_exponent = v.get_double("speed_exponent", c->speed_exponent);
  c->blades = v.get_int("blades", c->blades);
  c->accel_rotor_amplitude = v.get_vec3("accel_rotor_amplitude", c->accel_rotor_amplitude);
  c->accel_blade_amplitude = v.get_vec3("accel_blade_amplitude", c->accel_blade_amplitude);
  c->gyro_rotor_amplitude = v.get_vec3("gyro_rotor_amplitude", c->gyro_rotor_amplitude);
  c->gyro_blade_amplitude = v.get_vec3("gyro_blade_amplitude", c->gyro_blade_amplitude);
  c->accel_noise_density = v.get_double("accel_noise_density", c->accel_noise_density);
  c->gyro_noise_density = v.get_double("gyro_noise_density", c->gyro_noise_density);
  for (const io::YamlMap& b : v.get_maps("bursts")) c->bursts.push_back(parse_burst(b, imu_rate_hz));
  v.check_unknown();
  if (!(c->reference_speed >= 0.0)) v.fail("reference_speed", "must be >= 0 (0 = hover speed)");
  if (!(c->speed_exponent >= 0.0)) v.fail("speed_exponent", "must be >= 0");
  if (c->blades < 1) v.fail("blades", "must be >= 1");
  for (const char* k : {"accel_rotor_amplitude", "accel_blade_amplitude", "gyro_rotor_amplitude", "gyro_blade_amplitude"})
    require_nonnegative(v, k, v.get_vec3(k, Eigen::Vector3d::Zero()));
  if (!(c->accel_noise_density >= 0.0)) v.fail("accel_noise_density", "must be >= 0");
  if (!(c->gyro_noise_density >= 0.0)) v.fail("gyro_noise_density", "must be >= 0");
}

RotorDip parse_dip(const io::YamlMap& d, int rotor_count) {
  RotorDip dip;
  dip.t_s = d.get_double("t_s");
  dip.rotor = d.get_int("rotor");
  dip.duration_s = d.get_double("duration_s", dip.duration_s);
  dip.depth = d.get_double("depth", dip.depth);
  d.check_unknown();
  if (dip.rotor < 0 || dip.rotor >= rotor_count) d.fail("rotor", "must be a rotor index 0.." + std::to_string(rotor_count - 1));
  if (!(dip.duration_s > 0.0)) d.fail("duration_s", "must be > 0");
  if (!(dip.depth > 0.0 && dip.depth < 1.0)) d.fail("depth", "must be in (0, 1)");
  return dip;
}

void parse_dips(const io::YamlMap& m, int rotor_count, SensorFaultsConfig* c) {
  for (const io::YamlMap& d : m.get_maps("list")) c->dips.push_back(parse_dip(d, rotor_count));
  if (m.has("random")) {
    const io::YamlMap r = m.get_map_or_empty("random");
    RandomRotorDips& rd = c->random_dips;
    rd.rate_per_s = r.get_double("rate_per_s");
    rd.duration_s = r.get_double("duration_s", rd.duration_s);
    rd.depth = r.get_double("depth", rd.depth);
    rd.start_s = r.get_double("start_s", rd.start_s);
    rd.end_s = r.get_double("end_s", rd.end_s);
    r.check_unknown();
    if (!(rd.rate_per_s >= 0.0)) r.fail("rate_per_s", "must be >= 0");
    if (!(rd.duration_s > 0.0)) r.fail("duration_s", "must be > 0");
    if (!(rd.depth > 0.0 && rd.depth < 1.0)) r.fail("depth", "must be in (0, 1)");
    if (!(rd.start_s >= 0.0)) r.fail("start_s", "must be >= 0");
  } else {
    m.get_raw("random");
  }
  m.check_unknown();
}

}  // namespace

void parse_sensor_faults(const io::YamlMap& f, Scenario* s) {
  SensorFaultsConfig& c = s->faults;
  const double imu_rate = s->imu.noise.rate_hz;
  if (f.has("vibration")) {
    parse_vibration(f.get_map_or_empty("vibration"), imu_rate, &c.vibration);
  } else {
    f.get_raw("vibration");
  }
  {
    const io::YamlMap j = f.get_map_or_empty("imu_timestamps");
    c.imu_jitter_s = j.get_double("jitter_s", 0.0);
    c.imu_max_jitter_s = j.get_double("max_jitter_s", 3.0 * c.imu_jitter_s);
    j.check_unknown();
    if (!(c.imu_jitter_s >= 0.0 && c.imu_jitter_s <= 0.05)) j.fail("jitter_s", "must be in [0, 0.05] s");
    if (!(c.imu_max_jitter_s >= 0.0 && c.imu_max_jitter_s <= 0.1)) j.fail("max_jitter_s", "must be in [0, 0.1] s");
  }
  {
    const io::YamlMap t = f.get_map_or_empty("thrust_axis");
    c.thrust_tilt_deg = t.get_double("tilt_deg", 0.0);
    c.thrust_azimuth_deg = t.get_double("azimuth_deg", 0.0);
    t.check_unknown();
    if (!(c.thrust_tilt_deg >= 0.0 && c.thrust_tilt_deg <= 15.0)) t.fail("tilt_deg", "must be in [0, 15] deg");
    if (!std::isfinite(c.thrust_azimuth_deg)) t.fail("azimuth_deg", "must be finite");
  }
  c.thrust_coefficient_factor = f.get_double("thrust_coefficient_factor", 1.0);
  if (!(c.thrust_coefficient_factor >= 0.5 && c.thrust_coefficient_factor <= 2.0))
    f.fail("thrust_coefficient_factor", "must be in [0.5, 2]");
  {
    const io::YamlMap r = f.get_map_or_empty("rotor_telemetry");
    c.rotor_latency_s = r.get_double("latency_s", 0.0);
    c.rotor_quantization = r.get_double("quantization", 0.0);
    c.rotor_drop_probability = r.get_double("drop_probability", 0.0);
    c.rotor_max_consecutive_drops = r.get_int("max_consecutive_drops", c.rotor_max_consecutive_drops);
    r.check_unknown();
    if (!(c.rotor_latency_s >= 0.0 && c.rotor_latency_s <= 0.5)) r.fail("latency_s", "must be in [0, 0.5] s");
    if (!(c.rotor_quantization >= 0.0)) r.fail("quantization", "must be >= 0");
    if (!(c.rotor_drop_probability >= 0.0 && c.rotor_drop_probability < 1.0))
      r.fail("drop_probability", "must be in [0, 1)");
    if (c.rotor_max_consecutive_drops < 0) r.fail("max_consecutive_drops", "must be >= 0");
  }
  if (f.has("rotor_dips")) {
    parse_dips(f.get_map_or_empty("rotor_dips"), static_cast<int>(s->vehicle.rotors.size()), &c);
  } else {
    f.get_raw("rotor_dips");
  }
  f.check_unknown();
}

}  // namespace vid::sim::detail
