/// @file scenario.cpp
/// @brief Scenario YAML -> Scenario (strict keys). Vehicle/controller parsing lives in
/// scenario_vehicle.cpp.

#include "sim/scenario.h"

#include <Eigen/LU>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <sstream>

#include "io/errors.h"
#include "io/strict_yaml.h"
#include "scenario_parts.h"

namespace vid::sim {

namespace detail {

namespace {

Eigen::Vector4d vec4(const io::YamlMap& s, const std::string& key, const Eigen::Vector4d& fallback) {
  if (!s.has(key)) {
    s.get_raw(key);
    return fallback;
  }
  const auto v = s.get_doubles(key, 4);
  return Eigen::Vector4d(v[0], v[1], v[2], v[3]);
}

/// @brief A 4x4 rigid transform: any io::YamlMap matrix form, last row [0 0 0 1], rotation part
/// orthonormal with det +1.
Eigen::Matrix4d rigid_transform(const io::YamlMap& s, const std::string& key) {
  const Eigen::Matrix4d T = s.get_matrix4(key);
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) s.fail(key, "last row must be [0, 0, 0, 1]");
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0)
    s.fail(key, "rotation part is not a rotation matrix");
  return T;
}

}  // namespace

void parse_trajectory(const io::YamlMap& t, const std::filesystem::path& base_dir, TrajectoryConfig* c) {
  c->type = t.get_string("type", c->type);
  c->center = t.get_vec3("center", c->center);
  c->radius_m = t.get_double("radius_m", c->radius_m);
  c->height_amplitude_m = t.get_double("height_amplitude_m", c->height_amplitude_m);
  c->max_speed = t.get_double("max_speed", c->max_speed);
  c->max_accel = t.get_double("max_accel", c->max_accel);
  c->ramp_s = t.get_double("ramp_s", c->ramp_s);
  c->start_delay_s = t.get_double("start_delay_s", c->start_delay_s);
  const std::string yaw = t.get_string("yaw", "fixed");
  if (yaw == "fixed") {
    c->yaw_mode = YawMode::kFixed;
  } else if (yaw == "follow") {
    c->yaw_mode = YawMode::kFollow;
  } else if (yaw == "rate") {
    c->yaw_mode = YawMode::kRate;
  } else {
    t.fail("yaw", "expected fixed, follow or rate, got '" + yaw + "'");
  }
  c->yaw0 = t.get_double("yaw0", c->yaw0);
  c->yaw_rate = t.get_double("yaw_rate", c->yaw_rate);
  c->zigzag_length_m = t.get_double("zigzag_length_m", c->zigzag_length_m);
  c->zigzag_width_m = t.get_double("zigzag_width_m", c->zigzag_width_m);
  c->zigzag_legs = t.get_int("zigzag_legs", c->zigzag_legs);
  if (t.has("step_heights_m")) c->step_heights_m = t.get_doubles("step_heights_m");
  c->hold_s = t.get_double("hold_s", c->hold_s);
  c->box_min = t.get_vec3("box_min", c->box_min);
  c->box_max = t.get_vec3("box_max", c->box_max);
  c->waypoint_spacing_s = t.get_double("waypoint_spacing_s", c->waypoint_spacing_s);
  c->random_yaw_amplitude = t.get_double("random_yaw_amplitude", c->random_yaw_amplitude);
  const std::string file = t.get_string("file", "");
  if (!file.empty()) {
    const std::filesystem::path p(file);
    c->file = (p.is_absolute() ? p : base_dir / p).string();
  }
  c->fit_knot_spacing_s = t.get_double("fit_knot_spacing_s", c->fit_knot_spacing_s);
  t.check_unknown();
  if (c->type == "file" && c->file.empty()) t.fail("file", "type 'file' needs a TUM file");
  if (!(c->max_speed > 0.0)) t.fail("max_speed", "must be > 0");
  if (!(c->max_accel > 0.0)) t.fail("max_accel", "must be > 0");
  if (c->ramp_s < 0.0) t.fail("ramp_s", "must be >= 0");
  if (c->start_delay_s < 0.0) t.fail("start_delay_s", "must be >= 0");
  if (c->hold_s < 0.0) t.fail("hold_s", "must be >= 0");
}

namespace {

/// @brief rope / tether section; the tether has no damping fade (it snaps taut).
void parse_rope(const io::YamlMap& r, bool with_fade, RopeConfig* rope) {
  rope->enabled = r.get_bool("enabled", true);
  rope->anchor_W = r.get_vec3("anchor", rope->anchor_W);
  rope->rest_length_m = r.get_double("rest_length_m", rope->rest_length_m);
  rope->stiffness_N_per_m = r.get_double("stiffness_N_per_m", rope->stiffness_N_per_m);
  rope->damping_Ns_per_m = r.get_double("damping_Ns_per_m", rope->damping_Ns_per_m);
  rope->damping_ramp_m = with_fade ? r.get_double("damping_ramp_m", rope->damping_ramp_m) : 0.0;
  r.check_unknown();
  if (!(rope->rest_length_m >= 0.0)) r.fail("rest_length_m", "must be >= 0");
  if (!(rope->stiffness_N_per_m >= 0.0)) r.fail("stiffness_N_per_m", "must be >= 0");
  if (!(rope->damping_Ns_per_m >= 0.0)) r.fail("damping_Ns_per_m", "must be >= 0");
  if (!(rope->damping_ramp_m >= 0.0)) r.fail("damping_ramp_m", "must be >= 0");
}

/// @brief {t_s, force_N, duration_s} pulse (pushes, listed impacts).
PushConfig parse_pulse(const io::YamlMap& p, double default_duration_s) {
  PushConfig push;
  push.t_s = p.get_double("t_s");
  push.force_N = p.get_vec3("force_N", push.force_N);
  push.duration_s = p.get_double("duration_s", default_duration_s);
  p.check_unknown();
  if (!(push.duration_s > 0.0)) p.fail("duration_s", "must be > 0");
  return push;
}

/// @brief [lo, hi] with 0 < lo <= hi (a single number means lo = hi).
Eigen::Vector2d parse_range(const io::YamlMap& s, const std::string& key, const Eigen::Vector2d& fallback) {
  if (!s.has(key)) {
    s.get_raw(key);
    return fallback;
  }
  const YAML::Node n = s.get_raw(key);
  const std::vector<double> v = n.IsScalar() ? std::vector<double>(2, s.get_double(key)) : s.get_doubles(key, 2);
  if (!(v[0] > 0.0 && v[1] >= v[0])) s.fail(key, "expected [min, max] with 0 < min <= max");
  return Eigen::Vector2d(v[0], v[1]);
}

void parse_impacts(const io::YamlMap& s, EnvironmentConfig* e) {
  for (const io::YamlMap& p : s.get_maps("list")) e->impacts.push_back(parse_pulse(p, 0.03));
  if (s.has("random")) {
    const io::YamlMap r = s.get_map_or_empty("random");
    RandomImpactsConfig& c = e->random_impacts;
    c.rate_per_s = r.get_double("rate_per_s");
    const Eigen::Vector2d peak = parse_range(r, "peak_N", {c.peak_min_N, c.peak_max_N});
    const Eigen::Vector2d dur = parse_range(r, "duration_s", {c.duration_min_s, c.duration_max_s});
    c.peak_min_N = peak[0];
    c.peak_max_N = peak[1];
    c.duration_min_s = dur[0];
    c.duration_max_s = dur[1];
    c.start_s = r.get_double("start_s", c.start_s);
    c.end_s = r.get_double("end_s", c.end_s);
    c.directions = r.get_string("directions", c.directions);
    r.check_unknown();
    if (!(c.rate_per_s >= 0.0)) r.fail("rate_per_s", "must be >= 0");
    if (c.directions != "horizontal" && c.directions != "up" && c.directions != "any")
      r.fail("directions", "expected horizontal, up or any, got '" + c.directions + "'");
  } else {
    s.get_raw("random");
  }
  s.check_unknown();
}

ForceStepConfig parse_step(const io::YamlMap& p) {
  ForceStepConfig step;
  step.t_s = p.get_double("t_s");
  step.force_N = p.get_vec3("force_N", step.force_N);
  const std::string frame = p.get_string("frame", "world");
  if (frame != "world" && frame != "body") p.fail("frame", "expected world or body, got '" + frame + "'");
  step.body_frame = frame == "body";
  step.rise_s = p.get_double("rise_s", 0.0);
  p.check_unknown();
  if (!(step.rise_s >= 0.0)) p.fail("rise_s", "must be >= 0");
  return step;
}

void parse_from_file(const io::YamlMap& s, EnvironmentConfig* e) {
  const std::string file = s.get_string("file", "");
  s.check_unknown();
  if (file.empty()) s.fail("file", "missing force CSV (t_ns, Fx, Fy, Fz)");
  std::filesystem::path p(file);
  if (p.is_relative()) p = std::filesystem::path(s.file()).parent_path() / p;  // relative to the scenario
  std::error_code ec;
  if (!std::filesystem::is_regular_file(p, ec)) s.fail("file", "no such file '" + p.string() + "'");
  e->from_file = load_force_table(p);  // malformed rows: io::DatasetError "FILE:LINE: column N ..."
}

}  // namespace

void parse_forces(const io::YamlMap& f, EnvironmentConfig* e) {
  if (f.has("rope")) {
    parse_rope(f.get_map_or_empty("rope"), true, &e->rope);
  } else {
    f.get_raw("rope");
  }
  if (f.has("tether")) {
    parse_rope(f.get_map_or_empty("tether"), false, &e->tether);
  } else {
    f.get_raw("tether");
  }
  if (f.has("wind")) {
    const io::YamlMap w = f.get_map_or_empty("wind");
    e->wind.enabled = w.get_bool("enabled", true);
    e->wind.mean_mps = w.get_vec3("mean_mps", e->wind.mean_mps);
    e->wind.gust_std_mps = w.get_double("gust_std_mps", e->wind.gust_std_mps);
    e->wind.gust_time_constant_s = w.get_double("gust_time_constant_s", e->wind.gust_time_constant_s);
    e->wind.drag_N_per_mps = w.get_double("drag_N_per_mps", e->wind.drag_N_per_mps);
    w.check_unknown();
    if (e->wind.gust_std_mps < 0.0) w.fail("gust_std_mps", "must be >= 0");
    if (!(e->wind.gust_time_constant_s > 0.0)) w.fail("gust_time_constant_s", "must be > 0");
  } else {
    f.get_raw("wind");
  }
  for (const io::YamlMap& p : f.get_maps("pushes")) e->pushes.push_back(parse_pulse(p, PushConfig{}.duration_s));
  if (f.has("impacts")) {
    parse_impacts(f.get_map_or_empty("impacts"), e);
  } else {
    f.get_raw("impacts");
  }
  for (const io::YamlMap& p : f.get_maps("steps")) e->steps.push_back(parse_step(p));
  if (f.has("from_file")) {
    parse_from_file(f.get_map_or_empty("from_file"), e);
  } else {
    f.get_raw("from_file");
  }
  f.check_unknown();
}

void parse_mass(const io::YamlMap& m, EnvironmentConfig* e) {
  for (const io::YamlMap& p : m.get_maps("payloads")) {
    PayloadEvent ev;
    ev.t_s = p.get_double("t_s");
    ev.delta_kg = p.get_double("delta_kg");
    ev.ramp_s = p.get_double("ramp_s", ev.ramp_s);
    p.check_unknown();
    if (ev.ramp_s < 0.0) p.fail("ramp_s", "must be >= 0");
    e->payloads.push_back(ev);
  }
  if (m.has("loss")) {
    const io::YamlMap l = m.get_map_or_empty("loss");
    e->mass_loss.rate_kg_per_s = l.get_double("rate_kg_per_s");
    e->mass_loss.start_s = l.get_double("start_s", 0.0);
    e->mass_loss.end_s = l.get_double("end_s");
    l.check_unknown();
    if (e->mass_loss.rate_kg_per_s < 0.0) l.fail("rate_kg_per_s", "must be >= 0");
    if (e->mass_loss.end_s < e->mass_loss.start_s) l.fail("end_s", "must be >= start_s");
  } else {
    m.get_raw("loss");
  }
  m.check_unknown();
}

void parse_sensors(const io::YamlMap& root, Scenario* s) {
  {
    const io::YamlMap i = root.get_map_or_empty("imu");
    ImuNoise& n = s->imu.noise;
    n.rate_hz = i.get_double("rate_hz", n.rate_hz);
    n.gyro_noise_density = i.get_double("gyroscope_noise_density", n.gyro_noise_density);
    n.gyro_random_walk = i.get_double("gyroscope_random_walk", n.gyro_random_walk);
    n.accel_noise_density = i.get_double("accelerometer_noise_density", n.accel_noise_density);
    n.accel_random_walk = i.get_double("accelerometer_random_walk", n.accel_random_walk);
    s->imu.initial_gyro_bias = i.get_vec3("initial_gyro_bias", s->imu.initial_gyro_bias);
    s->imu.initial_accel_bias = i.get_vec3("initial_accel_bias", s->imu.initial_accel_bias);
    i.check_unknown();
    if (!(n.rate_hz > 0.0)) i.fail("rate_hz", "must be > 0");
    for (const char* k : {"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
                          "accelerometer_random_walk"}) {
      if (i.get_double(k, 0.0) < 0.0) i.fail(k, "must be >= 0");
    }
  }
  {
    const io::YamlMap r = root.get_map_or_empty("rotor_sensor");
    s->rotor.enabled = r.get_bool("enabled", true);
    s->rotor.sensor.rate_hz = r.get_double("rate_hz", 100.0);
    s->rotor.sensor.noise_density = r.get_double("noise_density", s->rotor.sensor.noise_density);
    r.check_unknown();
    if (!(s->rotor.sensor.rate_hz > 0.0)) r.fail("rate_hz", "must be > 0");
    if (s->rotor.sensor.noise_density < 0.0) r.fail("noise_density", "must be >= 0");
  }
  {
    const io::YamlMap g = root.get_map_or_empty("groundtruth");
    s->groundtruth_rate_hz = g.get_double("rate_hz", 200.0);
    if (g.has("initial_heading_deg")) {
      if (g.get_string("initial_heading_deg", "") == "random") {
        s->initial_heading_random = true;
      } else {
        s->initial_heading_deg = g.get_double("initial_heading_deg");
      }
    }
    g.check_unknown();
    if (!(s->groundtruth_rate_hz >= 200.0)) g.fail("rate_hz", "must be >= 200");
  }
  {
    const io::YamlMap c = root.get_map_or_empty("cameras");
    s->cameras.rate_hz = c.get_double("rate_hz", 30.0);
    s->cameras.images = c.get_bool("images", true);
    s->cameras.features = c.get_bool("features", true);
    s->cameras.time_offset_s = c.get_double("time_offset_s", 0.0);
    s->cameras.time_offset_jitter_s = c.get_double("time_offset_jitter_s", 0.0);
    if (!(std::abs(s->cameras.time_offset_s) <= 0.1)) c.fail("time_offset_s", "must be within +-0.1 s");
    if (!(s->cameras.time_offset_jitter_s >= 0.0 && s->cameras.time_offset_jitter_s <= 0.002))
      c.fail("time_offset_jitter_s", "must be in [0, 0.002] s (3 sigma stays below a sixth of a 30 Hz frame period)");
    int id = 0;
    for (const io::YamlMap& k : c.get_maps("list")) {
      CameraCalib cal;
      cal.cam_id = id++;
      cal.rate_hz = s->cameras.rate_hz;
      if (k.has("resolution")) {
        const auto r = k.get_doubles("resolution", 2);
        cal.width = static_cast<int>(r[0]);
        cal.height = static_cast<int>(r[1]);
      } else {
        k.get_raw("resolution");
      }
      cal.intrinsics = vec4(k, "intrinsics", cal.intrinsics);
      const std::string model = k.get_string("distortion_model", "radtan");
      if (model == "radtan" || model == "radial-tangential") {
        cal.distortion = DistortionModel::kRadTan;
      } else if (model == "equidistant") {
        cal.distortion = DistortionModel::kEquidistant;
      } else if (model == "none") {
        cal.distortion = DistortionModel::kNone;
      } else {
        k.fail("distortion_model", "expected radtan, equidistant or none");
      }
      cal.distortion_coeffs = vec4(k, "distortion_coeffs", cal.distortion_coeffs);
      const bool has_ic = k.has("T_imu_cam"), has_ci = k.has("T_cam_imu");
      if (has_ic == has_ci) k.fail("T_imu_cam", "give exactly one of T_imu_cam (pose of the camera in I) or T_cam_imu (Kalibr)");
      const Eigen::Matrix4d T = has_ic ? rigid_transform(k, "T_imu_cam") : Eigen::Matrix4d(rigid_transform(k, "T_cam_imu").inverse());
      if (has_ic) k.get_raw("T_cam_imu"); else k.get_raw("T_imu_cam");
      cal.T_IC.matrix() = T;
      cal.timeshift_cam_imu_s = k.get_double("timeshift_cam_imu", 0.0);
      k.check_unknown();
      if (cal.width < 16 || cal.height < 16) k.fail("resolution", "too small");
      if (!(cal.intrinsics[0] > 0.0 && cal.intrinsics[1] > 0.0)) k.fail("intrinsics", "focal lengths must be > 0");
      s->cameras.cameras.push_back(cal);
    }
    c.check_unknown();
    if (!(s->cameras.rate_hz > 0.0)) c.fail("rate_hz", "must be > 0");
  }
}

}  // namespace detail

Scenario load_scenario_string(const std::string& text, const std::string& name) {
  const YAML::Node root = io::YamlMap::parse_string(text, name);
  if (!root.IsMap()) throw io::ConfigError(name + ": expected a mapping at the top level");
  if (root["base"]) throw io::ConfigError(name + ": key 'base': only supported when loading from a file");
  return detail::scenario_from_node(root, name);
}

Scenario detail::scenario_from_node(const YAML::Node& root, const std::string& name) {
  const io::YamlMap r = io::YamlMap::from_node(root, name, "");
  Scenario s;
  s.file = name;
  s.name = r.get_string("name", std::filesystem::path(name).stem().string());
  s.seed = r.get_u64("seed", s.seed);
  s.duration_s = r.get_double("duration_s", s.duration_s);
  s.start_time_ns = static_cast<TimeNs>(r.get_u64("start_time_ns", static_cast<std::uint64_t>(s.start_time_ns)));
  s.noise = r.get_bool("noise", true);
  {
    const io::YamlMap p = r.get_map_or_empty("physics");
    s.physics_max_step_s = p.get_double("max_step_s", s.physics_max_step_s);
    s.control_rate_hz = p.get_double("control_rate_hz", s.control_rate_hz);
    p.check_unknown();
    if (!(s.physics_max_step_s > 0.0 && s.physics_max_step_s <= 0.001)) p.fail("max_step_s", "must be in (0, 0.001] (>= 1 kHz)");
    if (!(s.control_rate_hz > 0.0)) p.fail("control_rate_hz", "must be > 0");
  }
  const std::filesystem::path base = std::filesystem::path(name).parent_path();
  detail::parse_vehicle(r.get_map_or_empty("vehicle"), &s);
  detail::parse_controller(r.get_map_or_empty("controller"), &s.gains);
  detail::parse_trajectory(r.get_map_or_empty("trajectory"), base, &s.trajectory);
  s.trajectory.duration_s = s.duration_s;
  s.trajectory.seed = s.seed;
  detail::parse_forces(r.get_map_or_empty("forces"), &s.environment);
  detail::parse_mass(r.get_map_or_empty("mass"), &s.environment);
  detail::parse_sensors(r, &s);
  s.rotor.sensor.unit = s.rotor_unit;
  s.rotor.sensor.count = static_cast<int>(s.vehicle.rotors.size());
  detail::parse_sensor_faults(r.get_map_or_empty("sensor_faults"), &s);
  s.scene_node = r.get_raw("scene");
  s.render_node = r.get_raw("render");
  s.features_node = r.get_raw("features");
  detail::parse_ground(r, &s);
  r.check_unknown();
  if (!(s.duration_s > 0.0)) r.fail("duration_s", "must be > 0");
  return s;
}

namespace {

/// @brief Overlay @p over onto @p base: maps merge key by key, anything else replaces.
YAML::Node merge_nodes(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string k = kv.first.Scalar();
    out[k] = out[k] ? merge_nodes(out[k], kv.second) : YAML::Clone(kv.second);
  }
  return out;
}

/// @brief Parse a file and resolve its `base:` chain (paths relative to the file).
YAML::Node load_with_base(const std::filesystem::path& file, int depth) {
  if (depth > 8) throw io::ConfigError(file.string() + ": key 'base': chain deeper than 8 files");
  std::ifstream in(file);
  if (!in) throw io::ConfigError(file.string() + ": cannot open scenario file");
  std::stringstream ss;
  ss << in.rdbuf();
  YAML::Node root = io::YamlMap::parse_string(ss.str(), file.string());
  if (!root.IsMap()) throw io::ConfigError(file.string() + ": expected a mapping at the top level");
  if (!root["base"]) return root;
  if (!root["base"].IsScalar()) throw io::ConfigError(file.string() + ": key 'base': expected a file name");
  std::filesystem::path base_file(root["base"].Scalar());
  if (base_file.is_relative()) base_file = file.parent_path() / base_file;
  root.remove("base");
  return merge_nodes(load_with_base(base_file, depth + 1), root);
}

}  // namespace

void apply_run_options(Scenario& s, std::optional<std::uint64_t> seed, std::optional<double> duration_s,
                       const std::string& heading) {
  if (seed) {
    s.seed = *seed;
    s.trajectory.seed = *seed;
  }
  if (duration_s) {
    s.duration_s = *duration_s;
    s.trajectory.duration_s = *duration_s;
  }
  if (heading == "random") {
    s.initial_heading_random = true;
  } else if (!heading.empty()) {
    std::size_t used = 0;
    double deg = 0.0;
    try {
      deg = std::stod(heading, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != heading.size())
      throw std::invalid_argument("--initial-heading: expected degrees or 'random', got '" + heading + "'");
    s.initial_heading_deg = deg;
    s.initial_heading_random = false;
  }
}

Scenario load_scenario(const std::filesystem::path& file) {
  const YAML::Node root = load_with_base(file, 0);
  return detail::scenario_from_node(root, file.string());
}

VehicleParams vehicle_params_of(const Scenario& s) {
  VehicleParams v;
  v.mass_kg = s.vehicle.mass_kg;
  v.gravity = s.vehicle.gravity;
  const double factor = s.faults.thrust_coefficient_factor;
  for (const auto& r : s.vehicle.rotors)
    v.rotor_thrust_coefficients.push_back(factor == 1.0 ? r.thrust_coeff : factor * r.thrust_coeff);
  return v;
}

}  // namespace vid::sim
