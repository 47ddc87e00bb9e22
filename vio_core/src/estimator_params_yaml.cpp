#include "vio_core/estimator_params_yaml.h"

#include <sstream>
#include <stdexcept>

#include "io/number_format.h"
#include "io/strict_yaml.h"

namespace vid {
namespace {

// One table per field type, so loading and printing cannot drift apart.
struct DoubleField {
  const char* key;
  double EstimatorParams::*member;
};
struct IntField {
  const char* key;
  int EstimatorParams::*member;
};
struct BoolField {
  const char* key;
  bool EstimatorParams::*member;
};

#define VID_FIELD(name) {#name, &EstimatorParams::name}
const DoubleField kDoubles[] = {
    VID_FIELD(gravity),
    VID_FIELD(gyro_noise_density),
    VID_FIELD(gyro_random_walk),
    VID_FIELD(accel_noise_density),
    VID_FIELD(accel_random_walk),
    VID_FIELD(imu_rate_hz),
    VID_FIELD(thrust_noise_density),
    VID_FIELD(force_random_walk),
    VID_FIELD(force_rate_random_walk),
    VID_FIELD(thrust_scale_random_walk),
    VID_FIELD(thrust_delay_s),
    VID_FIELD(rotor_gap_s),
    VID_FIELD(rotor_gap_noise_scale),
    VID_FIELD(imu_gap_s),
    VID_FIELD(imu_gap_noise_scale),
    VID_FIELD(accel_chi2_multiplier),
    VID_FIELD(accel_noise_window_s),
    VID_FIELD(force_jump_threshold),
    VID_FIELD(force_jump_split_sigma),
    VID_FIELD(force_jump_min_step),
    VID_FIELD(landed_weight_fraction),
    VID_FIELD(airborne_weight_fraction),
    VID_FIELD(flight_phase_hold_s),
    VID_FIELD(smoother_lag_s),
    VID_FIELD(smoother_clone_period_s),
    VID_FIELD(pixel_noise_px),
    VID_FIELD(chi2_multiplier),
    VID_FIELD(triangulation_max_condition),
    VID_FIELD(zero_velocity_max_parallax_px),
    VID_FIELD(zero_velocity_sigma),
    VID_FIELD(landed_zero_velocity_sigma),
    VID_FIELD(health_window_s),
    VID_FIELD(health_max_chi2_rejected_fraction),
    VID_FIELD(health_starvation_s),
    VID_FIELD(init_window_s),
    VID_FIELD(init_lowpass_s),
    VID_FIELD(init_accel_std_max),
    VID_FIELD(init_gyro_std_max),
    VID_FIELD(init_dynamic_window_s),
    VID_FIELD(init_dynamic_window_mono_s),
    VID_FIELD(init_gravity_tolerance),
    VID_FIELD(init_freefall_thrust_ratio),
    VID_FIELD(init_sigma_roll_pitch),
    VID_FIELD(init_sigma_yaw),
    VID_FIELD(init_sigma_position),
    VID_FIELD(init_sigma_velocity),
    VID_FIELD(init_sigma_gyro_bias),
    VID_FIELD(init_sigma_accel_bias),
    VID_FIELD(init_sigma_force),
    VID_FIELD(init_sigma_force_rate),
    VID_FIELD(init_sigma_thrust_scale),
    VID_FIELD(init_sigma_time_offset),
    VID_FIELD(camera_time_jitter),
    VID_FIELD(max_velocity),
    VID_FIELD(max_position_sigma),
};
const IntField kInts[] = {
    VID_FIELD(window_size),
    VID_FIELD(min_track_length),
    VID_FIELD(max_features_per_update),
    VID_FIELD(health_min_tested_features),
    VID_FIELD(force_jump_window),
    VID_FIELD(init_dynamic_min_features),
};
const BoolField kBools[] = {
    VID_FIELD(use_fej),
    VID_FIELD(accel_update),
    VID_FIELD(accel_chi2_gating),
    VID_FIELD(accel_gate_downweight),
    VID_FIELD(force_jump_detection),
    VID_FIELD(visual_update),
    VID_FIELD(use_stereo),
    VID_FIELD(msckf_normal_equations),
};
#undef VID_FIELD

EstimatorParams from_map(const io::YamlMap& y) {
  EstimatorParams p;
  if (y.has("mode")) {
    const std::string s = y.get_string("mode");
    try {
      p.mode = mode_from_string(s);
    } catch (const std::invalid_argument&) {
      y.fail("mode", "expected imu or dynamics, got '" + s + "'");
    }
  }
  if (y.has("init_mode")) {
    const std::string s = y.get_string("init_mode");
    try {
      p.init_mode = init_mode_from_string(s);
    } catch (const std::invalid_argument&) {
      y.fail("init_mode", "expected auto, static or groundtruth, got '" + s + "'");
    }
  }
  if (y.has("force_frame")) {
    const std::string s = y.get_string("force_frame");
    try {
      p.force_frame = force_frame_from_string(s);
    } catch (const std::invalid_argument&) {
      y.fail("force_frame", "expected body or world, got '" + s + "'");
    }
  }
  for (const auto& f : kDoubles) p.*f.member = y.get_double(f.key, p.*f.member);
  for (const auto& f : kInts) p.*f.member = y.get_int(f.key, p.*f.member);
  for (const auto& f : kBools) p.*f.member = y.get_bool(f.key, p.*f.member);
  if (p.window_size < 2) y.fail("window_size", "must be at least 2, got " + std::to_string(p.window_size));
  if (!(p.gravity > 0.0)) y.fail("gravity", "must be positive");
  if (!(p.imu_rate_hz > 0.0)) y.fail("imu_rate_hz", "must be positive");
  if (p.force_jump_window < 2) y.fail("force_jump_window", "must be at least 2");
  if (!(p.force_jump_threshold > 0.0)) y.fail("force_jump_threshold", "must be positive");
  if (!(p.airborne_weight_fraction >= 0.0 && p.airborne_weight_fraction < p.landed_weight_fraction))
    y.fail("airborne_weight_fraction", "must be >= 0 and below landed_weight_fraction");
  if (!(p.flight_phase_hold_s >= 0.0)) y.fail("flight_phase_hold_s", "must be >= 0");
  if (!(p.init_sigma_time_offset >= 0.0 && p.init_sigma_time_offset <= 1.0))
    y.fail("init_sigma_time_offset", "must be in [0, 1] s");
  if (!(p.camera_time_jitter >= 0.0 && p.camera_time_jitter <= 1.0))
    y.fail("camera_time_jitter", "must be in [0, 1] s");
  y.check_unknown();
  return p;
}

}  // namespace

EstimatorParams load_estimator_params(const std::filesystem::path& path) {
  return from_map(io::YamlMap::load_file(path));
}

EstimatorParams load_estimator_params_string(const std::string& text, const std::string& name) {
  return from_map(io::YamlMap::load_string(text, name));
}

std::string to_yaml(const EstimatorParams& p) {
  std::ostringstream os;
  os << "mode: " << to_string(p.mode) << "\n"
     << "init_mode: " << to_string(p.init_mode) << "\n"
     << "force_frame: " << to_string(p.force_frame) << "\n";
  for (const auto& f : kInts) os << f.key << ": " << p.*f.member << "\n";
  for (const auto& f : kBools) os << f.key << ": " << (p.*f.member ? "true" : "false") << "\n";
  for (const auto& f : kDoubles) os << f.key << ": " << io::format_double(p.*f.member) << "\n";
  return os.str();
}

std::ostream& operator<<(std::ostream& os, const EstimatorParams& params) { return os << to_yaml(params); }

bool operator==(const EstimatorParams& a, const EstimatorParams& b) {
  if (a.mode != b.mode || a.init_mode != b.init_mode || a.force_frame != b.force_frame) return false;
  for (const auto& f : kDoubles) {
    if (a.*f.member != b.*f.member) return false;
  }
  for (const auto& f : kInts) {
    if (a.*f.member != b.*f.member) return false;
  }
  for (const auto& f : kBools) {
    if (a.*f.member != b.*f.member) return false;
  }
  return true;
}
}  // namespace vid
