/// @file test_estimator_params_yaml.cpp
/// @brief Estimator settings from YAML (vio_core_config): every field through print -> load,
/// error messages (file, line, key), the drift guard on the field tables, and equality.

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <sstream>
#include <string>

#include "io/errors.h"
#include "vio_core/estimator_params_yaml.h"

namespace vid::test {
namespace {

/// The message of the io::ConfigError that @p f throws ("" when it throws none).
std::string config_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(EstimatorParamsYaml, RoundTripEveryFieldChanged) {
  EstimatorParams p;
  p.mode = PropagationMode::kImu;
  p.init_mode = InitMode::kGroundTruth;
  p.window_size = 17;
  p.use_fej = false;
  p.gravity = 9.80665;
  p.gyro_noise_density = 1.7e-4;
  p.gyro_random_walk = 2e-5;
  p.accel_noise_density = 2.1e-3;
  p.accel_random_walk = 3.1e-3;
  p.imu_rate_hz = 200.5;
  p.thrust_noise_density = 0.07;
  p.force_random_walk = 0.3;
  p.force_frame = ForceFrame::kWorld;
  p.force_rate_random_walk = 0.25;
  p.init_sigma_force_rate = 0.35;
  p.rotor_gap_s = 0.03;
  p.rotor_gap_noise_scale = 7;
  p.imu_gap_s = 0.021;
  p.imu_gap_noise_scale = 3;
  p.accel_update = false;
  p.accel_chi2_gating = false;
  p.accel_chi2_multiplier = 2.5;
  p.force_jump_detection = false;
  p.force_jump_threshold = 25.5;
  p.force_jump_split_sigma = 1.5;
  p.force_jump_window = 32;
  p.visual_update = false;
  p.pixel_noise_px = 1.5;
  p.chi2_multiplier = 1.0 / 3.0;
  p.min_track_length = 4;
  p.max_features_per_update = 0;
  p.use_stereo = false;
  p.msckf_normal_equations = false;
  p.zero_velocity_max_parallax_px = 2.5;
  p.zero_velocity_sigma = 0.05;
  p.init_window_s = 0.7;
  p.init_accel_std_max = 0.2;
  p.init_gyro_std_max = 0.04;
  p.init_gravity_tolerance = 0.6;
  p.init_freefall_thrust_ratio = 0.25;
  p.init_sigma_roll_pitch = 0.03;
  p.init_sigma_yaw = 2e-4;
  p.init_sigma_position = 3e-4;
  p.init_sigma_velocity = 0.06;
  p.init_sigma_gyro_bias = 0.02;
  p.init_sigma_accel_bias = 0.2;
  p.init_sigma_force = 0.7;
  p.max_velocity = 40;
  p.max_position_sigma = 90;
  std::ostringstream os;
  os << p;
  const EstimatorParams q = load_estimator_params_string(os.str(), "est.yaml");
  EXPECT_EQ(to_yaml(q), os.str());
  EXPECT_EQ(q.mode, p.mode);
  EXPECT_EQ(q.init_mode, p.init_mode);
  EXPECT_EQ(q.force_frame, p.force_frame);
  EXPECT_EQ(q.window_size, 17);
  EXPECT_EQ(q.chi2_multiplier, 1.0 / 3.0);
  EXPECT_FALSE(q.use_stereo);
  EXPECT_FALSE(q.force_jump_detection);
  EXPECT_EQ(q.force_jump_window, 32);
  EXPECT_EQ(q.force_jump_threshold, 25.5);
  EXPECT_FALSE(q.msckf_normal_equations);
  EXPECT_EQ(q.max_features_per_update, 0);
  EXPECT_EQ(q.init_sigma_force, 0.7);
  EXPECT_EQ(q.zero_velocity_max_parallax_px, 2.5);
  EXPECT_EQ(q.zero_velocity_sigma, 0.05);
  // Defaults survive an empty file; errors name key and line.
  EXPECT_EQ(to_yaml(load_estimator_params_string("{}", "e.yaml")), to_yaml(EstimatorParams{}));
  EXPECT_EQ(config_error([] { load_estimator_params_string("mode: imu\nwindow_sise: 3\n", "e.yaml"); }),
            "e.yaml:2: unknown key 'window_sise'");
  EXPECT_EQ(config_error([] { load_estimator_params_string("mode: fast\n", "e.yaml"); }),
            "e.yaml:1: key 'mode': expected imu or dynamics, got 'fast'");
  EXPECT_EQ(config_error([] { load_estimator_params_string("force_frame: up\n", "e.yaml"); }),
            "e.yaml:1: key 'force_frame': expected body or world, got 'up'");
  EXPECT_EQ(config_error([] { load_estimator_params_string("window_size: 2.5\n", "e.yaml"); }),
            "e.yaml:1: key 'window_size': expected an integer, got '2.5'");
  EXPECT_EQ(config_error([] { load_estimator_params_string("use_fej: maybe\n", "e.yaml"); }),
            "e.yaml:1: key 'use_fej': expected true or false, got 'maybe'");
}

TEST(EstimatorParamsYaml, LoaderKnowsEveryField) {
  // Drift guard: the loader's tables hold 55 doubles, 6 ints, 8 bools and 3 enums (72 keys, one
  // line each), which is 544 bytes with padding. If vio_core adds or removes a field, this fails
  // until the tables in vio_core/src/estimator_params_yaml.cpp (and this count) are updated.
  const std::string y = to_yaml(EstimatorParams{});
  EXPECT_EQ(std::count(y.begin(), y.end(), '\n'), 72);
  EXPECT_EQ(sizeof(EstimatorParams), 544u)
      << "EstimatorParams changed: update the field tables in vio_core/src/estimator_params_yaml.cpp";
}

TEST(EstimatorParamsYaml, EqualityFollowsEveryPrintedField) {
  EstimatorParams p;
  p.mode = PropagationMode::kImu;
  p.window_size = 13;
  p.chi2_multiplier = 0.1 + 0.2;
  EXPECT_TRUE(load_estimator_params_string(to_yaml(p), "p.yaml") == p);  // parse(print(x)) == x
  EXPECT_FALSE(p == EstimatorParams{});
  // Every printed key, changed alone, makes the structs unequal (equality misses no field).
  const std::string y = to_yaml(EstimatorParams{});
  std::istringstream lines(y);
  for (std::string line; std::getline(lines, line);) {
    const std::string key = line.substr(0, line.find(':'));
    std::string value = line.substr(line.find(':') + 2);
    if (value == "true" || value == "false") value = value == "true" ? "false" : "true";
    else if (key == "mode") value = "imu";
    else if (key == "init_mode") value = "groundtruth";
    else if (key == "force_frame") value = value == "body" ? "world" : "body";
    else value = value + "1";  // 0.5 -> 0.51, 30 -> 301
    const EstimatorParams q = load_estimator_params_string(key + ": " + value + "\n", "q.yaml");
    EXPECT_FALSE(q == EstimatorParams{}) << key;
  }
}

}  // namespace
}  // namespace vid::test
