// Renderer: geometric accuracy through the distortion model (checkerboard corners), texture
// richness (FAST corners over the image) on every preset's scene, determinism, noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include "frontend/camera_model.h"
#include "sim/render/renderer.h"
#include "sim/render/scene.h"
#include "test_util.h"

namespace vid::sim {
namespace {

namespace fs = std::filesystem;

SceneConfig checkerboard_scene_config() {
  const fs::path preset = fs::path(VID_SOURCE_DIR) / "config/sim/checkerboard.yaml";
  if (fs::exists(preset)) return scene_config_from_scenario_file(preset.string());
  SceneConfig c;  // same layout as the preset, should it be renamed
  c.room_size = Eigen::Vector3d(8.0, 8.0, 3.5);
  c.room_center = Eigen::Vector3d(0.0, 0.0, 1.75);
  c.checkerboard.enabled = true;
  c.checkerboard.center = Eigen::Vector2d(0.0, 1.3);
  return c;
}

/// Median distance between detected corners and the true projections (nearest match).
double median_corner_error(const Scene& scene, const Renderer& renderer,
                           const Eigen::Isometry3d& T_WC, const FrameAppearance& app,
                           std::size_t* n_found) {
  const cv::Mat img = renderer.render(T_WC, app);
  const auto& k = scene.config().checkerboard;
  const cv::Size pattern(k.squares_x - 1, k.squares_y - 1);
  std::vector<cv::Point2f> found;
  *n_found = 0;
  if (!cv::findChessboardCorners(img, pattern, found,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
    return 1e9;
  }
  cv::cornerSubPix(img, found, cv::Size(5, 5), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  std::vector<Eigen::Vector2d> truth;
  const Eigen::Isometry3d T_CW = T_WC.inverse();
  for (const auto& p_W : scene.checkerboard_corners_W()) {
    Eigen::Vector2d uv;
    EXPECT_TRUE(renderer.camera().project(T_CW * p_W, &uv));
    truth.push_back(uv);
  }
  std::vector<double> err;
  for (const auto& f : found) {
    double best = 1e9;
    for (const auto& t : truth) best = std::min(best, (t - Eigen::Vector2d(f.x, f.y)).norm());
    err.push_back(best);
  }
  *n_found = found.size();
  std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
  return err[err.size() / 2];
}

TEST(Render, CheckerboardCornersMatchCameraModel) {
  const Scene scene(checkerboard_scene_config());
  const auto& k = scene.config().checkerboard;
  ASSERT_TRUE(k.enabled);
  const Renderer renderer(scene, test::vid_calib_distorted(), 2);
  // Board centre on the +x wall; views: straight on, oblique + rolled with the board near
  // the image corner (strong distortion), and closer.
  const Eigen::Vector3d board(scene.room_max().x(), k.center.x(), k.center.y());
  struct View {
    Eigen::Vector3d p, target;
    double roll;
  };
  const View views[] = {
      {board - Eigen::Vector3d(1.5, 0.0, 0.1), board, 0.0},
      {board - Eigen::Vector3d(1.2, -0.3, 0.2), board + Eigen::Vector3d(0, -0.45, -0.3), 0.2},
      {board - Eigen::Vector3d(0.9, 0.2, -0.1), board + Eigen::Vector3d(0, 0.15, 0.1), -0.1},
  };
  FrameAppearance noisy;
  noisy.noise_sigma = 2.0;  // as in the preset's render section
  noisy.noise_seed = 11;
  noisy.gain = 1.05;
  const std::size_t n_corners = (k.squares_x - 1) * (k.squares_y - 1);
  for (const auto& v : views) {
    for (const FrameAppearance& app : {FrameAppearance{}, noisy}) {
      std::size_t n = 0;
      const double med = median_corner_error(scene, renderer, test::look_at(v.p, v.target, v.roll),
                                             app, &n);
      EXPECT_EQ(n, n_corners);
      EXPECT_LT(med, 0.15) << "view at " << v.p.transpose() << " noise " << app.noise_sigma;
    }
  }
}

/// FAST (threshold 20) count and fraction of non-empty cells of an 8x6 grid.
void fast_stats(const cv::Mat& img, int* count, double* cell_fraction) {
  std::vector<cv::KeyPoint> kps;
  cv::FAST(img, kps, 20, true);
  *count = static_cast<int>(kps.size());
  std::vector<int> cells(48, 0);
  for (const auto& kp : kps) {
    const int cx = std::min(7, static_cast<int>(kp.pt.x * 8 / img.cols));
    const int cy = std::min(5, static_cast<int>(kp.pt.y * 6 / img.rows));
    ++cells[cy * 8 + cx];
  }
  *cell_fraction = std::count_if(cells.begin(), cells.end(), [](int c) { return c > 0; }) / 48.0;
}

/// Every preset scene (deduplicated), from the room centre looking at each wall, and from
/// the corners of the central area looking across the room and down at the floor.
TEST(Render, TextureGivesFastCornersEverywhereOnEveryPreset) {
  std::map<std::string, std::string> scenes;  // scene section text -> first preset using it
  const fs::path dir = fs::path(VID_SOURCE_DIR) / "config/sim";
  if (fs::exists(dir)) {
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.path().extension() != ".yaml") continue;
      const YAML::Node root = YAML::LoadFile(e.path().string());
      const std::string key = root["scene"] ? YAML::Dump(root["scene"]) : "";
      scenes.emplace(key, e.path().string());
    }
  }
  std::vector<std::pair<std::string, SceneConfig>> configs;
  for (const auto& [key, file] : scenes) {
    SceneConfig sc = scene_config_from_scenario_file(file);
    // Plain (low-texture) surfaces are the point of the hard presets: not checked here.
    if (!sc.low_texture.surfaces.empty() || sc.low_texture.box_fraction > 0.0) continue;
    configs.emplace_back(file, sc);
  }
  if (configs.empty()) configs.emplace_back("default", SceneConfig{});
  const CameraCalib calib = test::vid_calib_distorted();
  for (const auto& [name, config] : configs) {
    const Scene scene(config);
    const Renderer renderer(scene, calib, 2);
    const Eigen::Vector3d c = scene.config().room_center;
    const Eigen::Vector3d half = 0.5 * scene.config().room_size;
    std::vector<Eigen::Isometry3d> poses;
    for (int w = 0; w < 4; ++w) {
      const double yaw = w * M_PI / 2.0;
      const Eigen::Vector3d dir(std::cos(yaw), std::sin(yaw), -0.1);
      poses.push_back(test::look_at(c, c + dir));
    }
    for (const double sx : {-0.25, 0.25}) {
      const Eigen::Vector3d p = c + Eigen::Vector3d(sx * half.x(), 0.3 * half.y(), -0.2 * half.z());
      poses.push_back(test::look_at(p, p + Eigen::Vector3d(-sx, -0.6, -0.5)));
    }
    for (std::size_t i = 0; i < poses.size(); ++i) {
      ASSERT_TRUE(scene.is_free(poses[i].translation(), 0.1)) << name;
      int count = 0;
      double cells = 0;
      fast_stats(renderer.render(poses[i]), &count, &cells);
      EXPECT_GE(count, 300) << name << " pose " << i;
      EXPECT_GE(cells, 0.8) << name << " pose " << i;
    }
  }
}

TEST(Render, DeterministicForSameSeedAndNoiseDependsOnSeed) {
  SceneConfig c;
  c.room_size = Eigen::Vector3d(6, 5, 3);
  c.room_center = Eigen::Vector3d(0, 0, 1.5);
  c.texels_per_m = 150;
  c.texture_seed = 21;
  const Scene s1(c), s2(c);
  const Renderer r1(s1, test::vid_calib_distorted(), 2), r2(s2, test::vid_calib_distorted(), 2);
  const Eigen::Isometry3d T = test::look_at(Eigen::Vector3d(0.2, 0.1, 1.4), Eigen::Vector3d(3, 1, 0.5));
  RenderConfig rc;
  rc.noise_sigma = 3.0;
  rc.brightness_amplitude = 0.1;
  rc.brightness_jitter = 0.02;
  rc.seed = 99;
  const FrameAppearance a = appearance_for_frame(rc, 1'500'000'000, 0, 45);
  const cv::Mat i1 = r1.render(T, a), i2 = r2.render(T, a);
  EXPECT_EQ(cv::norm(i1, i2, cv::NORM_INF), 0.0);
  // Another seed: other noise (and gain), same geometry.
  RenderConfig rc2 = rc;
  rc2.seed = 100;
  const cv::Mat i3 = r1.render(T, appearance_for_frame(rc2, 1'500'000'000, 0, 45));
  EXPECT_GT(cv::norm(i1, i3, cv::NORM_L1), 0.0);
  // Different texture seed: a different image.
  c.texture_seed = 22;
  const Scene s3(c);
  const Renderer r3(s3, test::vid_calib_distorted(), 2);
  EXPECT_GT(cv::norm(r1.render(T), r3.render(T), cv::NORM_L1) / (640.0 * 480.0), 10.0);
}

TEST(Render, NoiseAndGainStatistics) {
  SceneConfig c;
  c.room_size = Eigen::Vector3d(6, 5, 3);
  c.room_center = Eigen::Vector3d(0, 0, 1.5);
  c.texels_per_m = 150;
  const Scene s(c);
  const Renderer r(s, test::vid_calib_distorted(), 1);
  const Eigen::Isometry3d T = test::look_at(Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(3, -1, 1));
  const cv::Mat clean = r.render(T);
  FrameAppearance a;
  a.noise_sigma = 4.0;
  a.noise_seed = 5;
  cv::Mat noisy = r.render(T, a), diff;
  clean.convertTo(diff, CV_32F);
  cv::Mat nf;
  noisy.convertTo(nf, CV_32F);
  diff = nf - diff;
  // Exclude saturated pixels, where clipping shrinks the noise.
  const cv::Mat mask = (clean > 20) & (clean < 235);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff, mean, sd, mask);
  EXPECT_NEAR(mean[0], 0.0, 0.1);
  EXPECT_NEAR(sd[0], std::sqrt(4.0 * 4.0 + 1.0 / 12.0), 0.2);  // plus 8-bit rounding
  FrameAppearance g;
  g.gain = 0.8;
  const cv::Mat darker = r.render(T, g);
  cv::Mat expect;
  clean.convertTo(expect, CV_32F, 0.8);
  cv::Mat df;
  darker.convertTo(df, CV_32F);
  EXPECT_LT(cv::norm(df - expect, cv::NORM_INF), 0.5 * 0.8 + 0.51);  // rounding of both images
}

TEST(Render, AppearanceDriftStaysWithinAmplitude) {
  RenderConfig rc;
  rc.brightness_amplitude = 0.1;
  rc.brightness_period_s = 4.0;
  double lo = 10, hi = 0;
  for (int i = 0; i < 200; ++i) {
    const auto a = appearance_for_frame(rc, i * 33'333'333LL, 0, i);
    lo = std::min(lo, a.gain);
    hi = std::max(hi, a.gain);
  }
  EXPECT_GE(lo, 0.9 - 1e-12);
  EXPECT_LE(hi, 1.1 + 1e-12);
  EXPECT_GT(hi - lo, 0.15);  // it does drift over a period
}

}  // namespace
}  // namespace vid::sim
