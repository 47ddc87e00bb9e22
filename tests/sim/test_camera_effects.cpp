// Camera effects of the renderer (camera_effects.h): motion blur measured on a moving edge,
// vignetting against its model, shot + read noise variance on a flat patch, the rolling
// shutter's row shift under a known yaw rate, effects-off byte identity, config errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <string>
#include <vector>
#include <yaml-cpp/yaml.h>

#include "io/errors.h"
#include "io/strict_yaml.h"
#include "sim/render/renderer.h"
#include "sim/render/scene.h"
#include "../sim_render/test_util.h"

namespace vid::sim {
namespace {

/// 8 x 8 x 3.5 m room with the 9 x 7 board (0.08 m squares) on the +x wall at z = 1.3.
SceneConfig board_room() {
  SceneConfig c;
  c.room_size = Eigen::Vector3d(8.0, 8.0, 3.5);
  c.room_center = Eigen::Vector3d(0.0, 0.0, 1.75);
  c.texels_per_m = 150;
  c.boxes.count = 0;
  c.checkerboard.enabled = true;
  c.checkerboard.center = Eigen::Vector2d(0.0, 1.3);
  return c;
}

/// Camera at distance d in front of the +x wall, looking at the board centre.
Eigen::Isometry3d facing_board(double d) {
  return test::look_at(Eigen::Vector3d(4.0 - d, 0.0, 1.3), Eigen::Vector3d(4.0, 0.0, 1.3));
}

/// Mean variance [px^2] of the gradient profile of the vertical edges crossed by rows
/// [y0, y1) within columns [x0, x1). Blurs add their variances (a box of length B: B^2 / 12).
double mean_edge_variance(const cv::Mat& img, int y0, int y1, int x0, int x1) {
  std::vector<double> p(static_cast<std::size_t>(x1 - x0), 0.0);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) p[x - x0] += img.at<std::uint8_t>(y, x);
  }
  std::vector<double> g(p.size() - 1);
  for (std::size_t i = 0; i + 1 < p.size(); ++i) g[i] = std::abs(p[i + 1] - p[i]);
  const double g_max = *std::max_element(g.begin(), g.end());
  std::vector<double> vars;
  constexpr int kHalf = 9;  // squares are ~25 px wide: one edge per window
  for (int i = kHalf; i + kHalf < static_cast<int>(g.size()); ++i) {
    if (g[i] < 0.3 * g_max) continue;
    if (!std::all_of(g.begin() + i - kHalf, g.begin() + i + kHalf + 1, [&](double v) { return v <= g[i]; })) continue;
    double w = 0.0, m1 = 0.0, m2 = 0.0;
    for (int k = -kHalf; k <= kHalf; ++k) {
      w += g[i + k];
      m1 += k * g[i + k];
      m2 += k * k * g[i + k];
    }
    vars.push_back(m2 / w - (m1 / w) * (m1 / w));
  }
  double mean = 0.0;
  for (double v : vars) mean += v / static_cast<double>(vars.size());
  return vars.size() >= 4 ? mean : -1.0;
}

TEST(CameraEffects, MotionBlurWidensWithExposureTimesSpeed) {
  const Scene scene(board_room());
  const CameraCalib calib = test::vid_calib_distorted();
  const Renderer r(scene, calib, 2);
  const double d = 1.2;
  const Eigen::Isometry3d T0 = facing_board(d);
  // Moving along the camera's x axis at speed v: edges move f v / d px/s.
  auto width = [&](double exposure_s, double v) {
    const PoseAtTime T_at = [&](double dt) {
      Eigen::Isometry3d T = T0;
      T.translation() += T0.linear().col(0) * v * dt;
      return T;
    };
    FrameAppearance app;
    app.exposure_s = exposure_s;
    app.exposure_samples = 64;
    cv::Mat img;
    r.render(T_at, app, &img);
    const int cy = static_cast<int>(calib.intrinsics[3]), cx = static_cast<int>(calib.intrinsics[2]);
    return mean_edge_variance(img, cy - 5, cy + 5, cx - 100, cx + 100);
  };
  const double v0 = width(0.0, 1.0), v1 = width(0.004, 1.0), v2 = width(0.008, 1.0);
  const double v2b = width(0.004, 2.0);
  ASSERT_GT(v0, 0.0);
  ASSERT_GT(v2, 0.0);
  // Smear length measured from the added variance (box of length B: B^2 / 12).
  auto smear = [&](double v) { return std::sqrt(12.0 * std::max(0.0, v - v0)); };
  const double f = calib.intrinsics[0];
  const double blur_8ms = f * 1.0 * 0.008 / d;  // predicted smear [px] at 8 ms, 1 m/s
  EXPECT_LT(v0, v1);
  EXPECT_LT(v1, v2);
  // The smear grows with exposure * speed: same product, same smear.
  EXPECT_NEAR(smear(v2b), smear(v2), 0.1 * smear(v2));
  EXPECT_NEAR(smear(v2), blur_8ms, 0.2 * blur_8ms) << "var0 " << v0 << " var(8 ms) " << v2;
  EXPECT_NEAR(smear(v1), 0.5 * blur_8ms, 0.25 * blur_8ms);
}

TEST(CameraEffects, VignettingFallsOffTowardCornersPerModel) {
  const Scene scene(board_room());
  const CameraCalib calib = test::vid_calib_distorted();
  const Renderer r(scene, calib, 1);
  const Eigen::Isometry3d T = test::look_at(Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(4, 1, 1.2));
  FrameAppearance plain, vig;
  vig.vignetting = 0.4;
  const cv::Mat a = r.render(T, plain), b = r.render(T, vig);
  const double cx = calib.intrinsics[2], cy = calib.intrinsics[3];
  const double dx = std::max(cx, 639 - cx), dy = std::max(cy, 479 - cy);
  double err_sum = 0.0, corner_ratio = 0.0, corner_model = 0.0;
  int n = 0, n_corner = 0;
  for (int y = 0; y < 480; y += 2) {
    for (int x = 0; x < 640; x += 2) {
      const double clean = a.at<std::uint8_t>(y, x);
      if (clean < 80.0) continue;  // keep the 8-bit rounding small against the level
      const double rho2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (dx * dx + dy * dy);
      const double model = vignetting_factor(0.4, rho2), ratio = b.at<std::uint8_t>(y, x) / clean;
      err_sum += std::abs(ratio - model);
      ++n;
      if (rho2 > 0.85) {
        corner_ratio += ratio;
        corner_model += model;
        ++n_corner;
      }
    }
  }
  ASSERT_GT(n, 10000);
  ASSERT_GT(n_corner, 100);
  EXPECT_LT(err_sum / n, 0.006);  // rounding of two 8-bit images at >= 80 levels
  EXPECT_NEAR(corner_ratio / n_corner, corner_model / n_corner, 0.01);
  EXPECT_LT(corner_ratio / n_corner, 0.68);  // 1 - 0.4 rho^2 at rho^2 > 0.85
}

TEST(CameraEffects, NoiseVarianceMatchesShotPlusReadModel) {
  SceneConfig c = board_room();
  c.checkerboard.enabled = false;
  c.low_texture.surfaces = {"+x", "-x", "+y", "-y", "floor", "ceiling"};
  c.low_texture.noise_amplitude = 0.0;  // exactly uniform walls
  const Scene scene(c);
  const Renderer r(scene, test::vid_calib_distorted(), 1);
  const Eigen::Isometry3d T = facing_board(2.0);
  const cv::Rect patch(270, 190, 100, 100);
  cv::Scalar mean, sd;
  cv::meanStdDev(r.render(T)(patch), mean, sd);
  ASSERT_LT(sd[0], 0.5) << "the patch must be flat";
  const double level = mean[0];
  struct Case { double gain, analog_gain, read, electrons; };
  for (const Case& k : {Case{1.0, 1.0, 1.5, 10.0}, Case{1.2, 3.0, 1.0, 40.0}, Case{0.8, 1.0, 0.0, 5.0}}) {
    FrameAppearance app;
    app.gain = k.gain;
    app.analog_gain = k.analog_gain;
    app.noise_sigma = k.read;
    app.electrons_per_level = k.electrons;
    app.noise_seed = 11;
    cv::Mat noisy;
    r.render(T, app, &noisy);
    cv::meanStdDev(noisy(patch), mean, sd);
    const double signal = k.gain * level;
    ASSERT_LT(signal + 4 * std::sqrt(signal), 250.0) << "no clipping";
    const double model = std::pow(k.read * k.analog_gain, 2) + signal * k.analog_gain / k.electrons + 1.0 / 12.0;
    EXPECT_NEAR(sd[0] * sd[0], model, 0.06 * model) << "gain " << k.gain << " G " << k.analog_gain;
    EXPECT_NEAR(mean[0], signal, 0.1);
  }
}

TEST(CameraEffects, RollingShutterShiftsRowsByLineDelayTimesYawRate) {
  SceneConfig c = board_room();
  c.checkerboard.enabled = false;  // rich texture everywhere for the row correlation
  const Scene scene(c);
  const CameraCalib calib = test::vid_calib_distorted();
  const Renderer r(scene, calib, 2);
  const Eigen::Isometry3d T0 = facing_board(2.5);
  const double yaw_rate = 1.0, line_delay = 30e-6;  // [rad/s], [s/row]
  const PoseAtTime T_at = [&](double dt) {  // turning right: about the camera's +y (down) axis
    Eigen::Isometry3d T = T0;
    T.linear() = T0.linear() * Eigen::AngleAxisd(yaw_rate * dt, Eigen::Vector3d::UnitY()).toRotationMatrix();
    return T;
  };
  FrameAppearance app;
  app.line_delay_s = line_delay;
  cv::Mat rs, gs;
  r.render(T_at, app, &rs);
  r.render(T0, FrameAppearance{}, &gs);
  const int cx = static_cast<int>(calib.intrinsics[2]);
  for (const int y : {60, 240, 420}) {
    // Sub-pixel s with rs(x) = gs(x + s) over a central band (SSD minimum + parabola): the
    // scene moved by -s in the rolling-shutter row.
    auto ssd = [&](int s) {
      double e = 0.0;
      for (int yy = y - 2; yy <= y + 2; ++yy) {
        for (int x = cx - 80; x <= cx + 80; ++x) {
          const double dv = rs.at<std::uint8_t>(yy, x) - gs.at<std::uint8_t>(yy, x + s);
          e += dv * dv;
        }
      }
      return e;
    };
    int best = 0;
    for (int s = -12; s <= 12; ++s) best = ssd(s) < ssd(best) ? s : best;
    const double em = ssd(best - 1), e0 = ssd(best), ep = ssd(best + 1);
    const double shift = best + 0.5 * (em - ep) / (em - 2 * e0 + ep);
    // Turning right by theta moves the scene by -f theta (1 + x_n^2) px, ~1 near the centre.
    const double predicted = -calib.intrinsics[0] * yaw_rate * y * line_delay;
    EXPECT_NEAR(-shift, predicted, 0.25 + 0.06 * std::abs(predicted)) << "row " << y;
  }
}

TEST(CameraEffects, EffectsOffIsByteIdentical) {
  SceneConfig c = board_room();
  c.boxes.count = 4;
  const Scene scene(c);
  const Renderer r(scene, test::vid_calib_distorted(), 2);
  const Eigen::Isometry3d T = test::look_at(Eigen::Vector3d(0.3, -0.2, 1.4), Eigen::Vector3d(4, 1, 1.0));
  RenderConfig rc;  // today's keys only; the new ones at their defaults
  rc.noise_sigma = 2.0;
  rc.brightness_amplitude = 0.05;
  rc.brightness_jitter = 0.01;
  rc.seed = 7;
  const FrameAppearance app = appearance_for_frame(rc, 2'000'000'000, 0, 60);
  EXPECT_FALSE(app.sensor_effects());
  const cv::Mat old_api = r.render(T, app);
  cv::Mat new_api;
  r.render(PoseAtTime([&](double) { return T; }), app, &new_api);
  EXPECT_EQ(cv::norm(old_api, new_api, cv::NORM_INF), 0.0);
  // The parts by hand: radiance + the sensor loop of before (gain, offset, table noise).
  std::vector<float> rad(640 * 480);
  r.render_radiance(T, rad.data());
  const cv::Mat clean = r.render(T);
  int mismatches = 0;
  for (int i = 0; i < 640 * 480; ++i) {
    const float v = std::clamp(rad[i], 0.0f, 255.0f) + 0.5f;
    mismatches += clean.data[i] != static_cast<std::uint8_t>(v);
  }
  EXPECT_EQ(mismatches, 0);
  // A row-by-row readout with no line delay is the global-shutter image bit for bit.
  std::vector<float> rows(640 * 480);
  r.render_radiance_rows(PoseAtTime([&](double) { return T; }), 0.0, 0.0, rows.data());
  EXPECT_TRUE(std::equal(rad.begin(), rad.end(), rows.begin()));
}

TEST(CameraEffects, AutoExposureRaisesExposureThenGain) {
  AutoExposureConfig c;
  c.enabled = true;
  c.target_level = 110;
  c.max_exposure_s = 0.02;
  c.max_gain = 8;
  c.rate = 0.5;
  AutoExposure ae(c, 0.01);
  EXPECT_DOUBLE_EQ(ae.factor(), 1.0);
  ae.update(110.0 / 5.0);  // first metering: the full correction, factor 5
  EXPECT_NEAR(ae.factor(), 5.0, 1e-12);
  EXPECT_DOUBLE_EQ(ae.exposure_s(), 0.02);
  EXPECT_NEAR(ae.gain(), 2.5, 1e-12);
  ae.update(110.0 * 4.0);  // 4x too bright: half the log error per frame -> factor / 2
  EXPECT_NEAR(ae.factor(), 2.5, 1e-12);
  EXPECT_NEAR(ae.gain(), 1.25, 1e-12);
  EXPECT_NEAR(flicker_factor(0.2, 100.0, 0.3, 0.123, 0.0),
              1.0 + 0.2 * std::sin(2.0 * std::numbers::pi * 100.0 * 0.123 + 0.3), 1e-12);
  EXPECT_NEAR(flicker_factor(0.2, 100.0, 0.3, 0.123, 0.010), 1.0, 1e-12);  // whole periods
}

void expect_render_error(const std::string& yaml, const std::string& key) {
  const YAML::Node node = io::YamlMap::parse_string(yaml, "t.yaml");
  try {
    parse_render_config(node, "t.yaml");
    ADD_FAILURE() << "accepted: " << yaml;
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'" + key + "'"), std::string::npos) << e.what();
  }
}

TEST(CameraEffects, BadConfigValuesNameTheKey) {
  expect_render_error("exposure_s: -0.001", "render.exposure_s");
  expect_render_error("exposure_samples: 0", "render.exposure_samples");
  expect_render_error("line_delay_s: -1.0e-5", "render.line_delay_s");
  expect_render_error("vignetting: 1.5", "render.vignetting");
  expect_render_error("electrons_per_level: -3", "render.electrons_per_level");
  expect_render_error("illumination: 0", "render.illumination");
  expect_render_error("flicker_amplitude: -0.1", "render.flicker_amplitude");
  expect_render_error("exposure_s: 0.01\nauto_exposure: {max_gain: 0.5}", "render.auto_exposure.max_gain");
  expect_render_error("auto_exposure: {target_level: 100}", "render.exposure_s");
  expect_render_error("auto_exposure_typo: 1", "render.auto_exposure_typo");
  const YAML::Node scene = io::YamlMap::parse_string("low_texture: {surfaces: [wall]}", "s.yaml");
  try {
    parse_scene_config(scene, "s.yaml");
    ADD_FAILURE() << "accepted a bad surface name";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.low_texture.surfaces"), std::string::npos) << e.what();
  }
  // Everything valid parses, defaults stay off.
  const RenderConfig def = parse_render_config(YAML::Node(), "t.yaml");
  EXPECT_EQ(def.exposure_s, 0.0);
  EXPECT_FALSE(def.auto_exposure.enabled);
}

}  // namespace
}  // namespace vid::sim
