// FeatureSimulator: exact projections of the landmarks, visibility, counts, track lifetimes,
// stereo, determinism, pixel noise, config parsing.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <set>

#include "frontend/camera_model.h"
#include "io/errors.h"
#include "sim/render/feature_simulator.h"
#include "test_util.h"

namespace vid::sim {
namespace {

SceneConfig feature_scene() {
  SceneConfig c;
  c.room_size = Eigen::Vector3d(10.0, 8.0, 3.5);
  c.room_center = Eigen::Vector3d(0.0, 0.0, 1.75);
  c.texels_per_m = 40;  // textures are not used here; keep the build fast
  c.texture_seed = 12;
  c.boxes.count = 8;
  return c;
}

/// VID stereo rig: camera-to-IMU rotation and translation of docs/design.md §6, 5 cm baseline.
std::vector<CameraCalib> stereo_rig() {
  std::vector<CameraCalib> cams = {test::vid_calib_distorted(0), test::vid_calib_distorted(1)};
  Eigen::Matrix3d R_IC;
  R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  cams[0].T_IC.linear() = R_IC;
  cams[0].T_IC.translation() = Eigen::Vector3d(0.18875, 0.00175, 0.0555);
  cams[1].T_IC = cams[0].T_IC;
  cams[1].T_IC.translation() += R_IC * Eigen::Vector3d(0.05, 0, 0);
  return cams;
}

/// IMU pose at frame k (30 Hz): a circle of 1.5 m radius at 1.5 m height, yaw turning
/// 1.5x as fast as the position, with some roll/pitch wobble.
Eigen::Isometry3d imu_pose(int k) {
  const double t = k / 30.0, a = 0.35 * t;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1.5 * std::cos(a), 1.5 * std::sin(a), 1.5 + 0.2 * std::sin(t));
  T.linear() = (Eigen::AngleAxisd(1.5 * a, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(0.1 * std::sin(2 * t), Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(0.08 * std::cos(1.3 * t), Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  return T;
}

constexpr int kFrames = 240;  // 8 s at 30 Hz

class FeatureSimTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { scene_ = new Scene(feature_scene()); }
  static void TearDownTestSuite() {
    delete scene_;
    scene_ = nullptr;
  }
  static std::vector<FeatureFrame> run(const FeatureSimConfig& cfg, FeatureSimulator** keep = nullptr) {
    auto* sim = new FeatureSimulator(*scene_, stereo_rig(), cfg);
    std::vector<FeatureFrame> frames;
    for (int k = 0; k < kFrames; ++k) frames.push_back(sim->step(1'000'000'000LL + k * 33'333'333LL, imu_pose(k)));
    if (keep) {
      *keep = sim;
    } else {
      delete sim;
    }
    return frames;
  }
  static Scene* scene_;
};
Scene* FeatureSimTest::scene_ = nullptr;

TEST_F(FeatureSimTest, NoiseFreeObservationsAreExactVisibleProjections) {
  FeatureSimulator* sim = nullptr;
  const auto frames = run(FeatureSimConfig{}, &sim);
  std::unique_ptr<FeatureSimulator> owner(sim);
  const auto cams = stereo_rig();
  std::vector<std::unique_ptr<CameraModel>> models;
  for (const auto& c : cams) models.push_back(CameraModel::create(c));
  std::size_t n = 0;
  double worst = 0.0;
  for (int k = 0; k < kFrames; ++k) {
    for (const auto& ob : frames[k].observations) {
      ASSERT_LT(ob.feature_id, sim->landmarks().size());
      const Landmark& lm = sim->landmarks()[ob.feature_id];
      ASSERT_EQ(lm.id, ob.feature_id);
      const Eigen::Isometry3d T_WC = imu_pose(k) * cams[ob.cam_id].T_IC;
      // Independent transform path: R^T (p - t).
      const Eigen::Vector3d p_C = T_WC.linear().transpose() * (lm.p_W - T_WC.translation());
      Eigen::Vector2d uv;
      ASSERT_TRUE(models[ob.cam_id]->project(p_C, &uv));
      worst = std::max(worst, (uv - ob.uv).cwiseAbs().maxCoeff());
      EXPECT_TRUE(ob.has_norm);
      EXPECT_NEAR((ob.uv_norm - p_C.head<2>() / p_C.z()).norm(), 0.0, 1e-12);
      EXPECT_TRUE(models[ob.cam_id]->in_image(ob.uv));
      // Not occluded: the first surface along the ray is the landmark itself.
      const auto hit = scene_->raycast(T_WC.translation(), lm.p_W - T_WC.translation());
      ASSERT_TRUE(hit);
      EXPECT_LT((*hit - lm.p_W).norm(), 1e-6 * (1.0 + p_C.norm()));
      ++n;
    }
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(n, static_cast<std::size_t>(kFrames * 2 * 100));
  // Every landmark lies on a surface of the scene (room or box face rectangle).
  for (const auto& lm : sim->landmarks()) {
    bool on = false;
    for (const Surface& s : scene_->surfaces()) {
      const double du = lm.p_W[s.u_axis] - s.u0, dv = lm.p_W[s.v_axis] - s.v0;
      on = on || (lm.p_W[s.normal_axis] == s.plane && du >= -1e-9 && du <= s.u_len + 1e-9 &&
                  dv >= -1e-9 && dv <= s.v_len + 1e-9);
    }
    EXPECT_TRUE(on) << lm.id;
  }
}

TEST_F(FeatureSimTest, CountsLifetimesAndStereo) {
  const auto frames = run(FeatureSimConfig{});
  std::map<std::uint64_t, std::pair<int, int>> span;  // id -> first, last frame seen
  std::map<std::uint64_t, int> frames_seen;
  double sum_cam[2] = {0, 0};
  int min_cam = 1 << 30, max_cam = 0;
  std::size_t both = 0, cam0 = 0;
  for (int k = 0; k < kFrames; ++k) {
    int per_cam[2] = {0, 0};
    std::set<std::uint64_t> ids[2];
    for (const auto& ob : frames[k].observations) {
      ++per_cam[ob.cam_id];
      ids[ob.cam_id].insert(ob.feature_id);
    }
    for (const auto id : ids[0]) both += ids[1].count(id);
    cam0 += ids[0].size();
    std::set<std::uint64_t> all = ids[0];
    all.insert(ids[1].begin(), ids[1].end());
    for (const auto id : all) {
      auto it = span.find(id);
      if (it == span.end()) span[id] = {k, k};
      else it->second.second = k;
      ++frames_seen[id];
    }
    for (int c = 0; c < 2; ++c) {
      sum_cam[c] += per_cam[c];
      min_cam = std::min(min_cam, per_cam[c]);
      max_cam = std::max(max_cam, per_cam[c]);
    }
  }
  for (int c = 0; c < 2; ++c) {
    const double mean = sum_cam[c] / kFrames;
    EXPECT_GT(mean, 140.0) << "cam " << c;
    EXPECT_LT(mean, 175.0) << "cam " << c;
  }
  EXPECT_GT(min_cam, 110);
  EXPECT_LT(max_cam, 200);  // stereo spawning does not double the count
  // Stable ids: a track is seen in one unbroken run of frames and never comes back.
  double lifetime = 0;
  for (const auto& [id, s] : span) {
    EXPECT_EQ(s.second - s.first + 1, frames_seen[id]) << "id " << id << " reappeared";
    lifetime += s.second - s.first + 1;
  }
  lifetime /= static_cast<double>(span.size());
  EXPECT_GT(lifetime, 10.0);  // tracks persist over many frames ...
  EXPECT_LT(lifetime, 60.0);  // ... but do end (drops, leaving the view)
  // Stereo: most features of cam0 are seen by cam1 too.
  EXPECT_GT(static_cast<double>(both) / cam0, 0.85);
}

TEST_F(FeatureSimTest, DeterministicAndNoiseDoesNotChangeTracks) {
  FeatureSimConfig noisy;
  noisy.pixel_noise_sigma = 0.7;
  noisy.seed = 3;
  FeatureSimConfig clean = noisy;
  clean.pixel_noise_sigma = 0.0;
  const auto a = run(noisy), b = run(noisy), c = run(clean);
  double sum2 = 0;
  std::size_t n = 0;
  for (int k = 0; k < kFrames; ++k) {
    ASSERT_EQ(a[k].observations.size(), b[k].observations.size());
    ASSERT_EQ(a[k].observations.size(), c[k].observations.size());
    for (std::size_t i = 0; i < a[k].observations.size(); ++i) {
      const auto &oa = a[k].observations[i], &ob = b[k].observations[i], &oc = c[k].observations[i];
      EXPECT_EQ(oa.uv, ob.uv);
      EXPECT_EQ(oa.feature_id, oc.feature_id);
      EXPECT_EQ(oa.cam_id, oc.cam_id);
      sum2 += (oa.uv - oc.uv).squaredNorm();
      n += 2;
      // uv_norm is the exact model's undistortion of the noisy pixel.
      ASSERT_TRUE(oa.has_norm);
    }
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.7, 0.07);
  FeatureSimConfig other = noisy;
  other.seed = 4;
  const auto d = run(other);
  EXPECT_NE(d[5].observations.front().uv, a[5].observations.front().uv);
}

TEST(FeatureSimConfig, ParsesAndRejects) {
  const auto c = parse_feature_sim_config(
      YAML::Load("{target_per_camera: 120, pixel_noise_sigma: 0.5, drop_probability: 0.03, "
                 "grid: [10, 8], seed: 9, max_incidence_deg: 75}"),
      "f.yaml");
  EXPECT_EQ(c.target_per_camera, 120);
  EXPECT_DOUBLE_EQ(c.pixel_noise_sigma, 0.5);
  EXPECT_EQ(c.grid_cols, 10);
  EXPECT_EQ(c.grid_rows, 8);
  EXPECT_EQ(c.seed, 9u);
  auto err = [](const char* text) {
    try {
      parse_feature_sim_config(YAML::Load(text), "f.yaml");
    } catch (const io::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("{targets: 3}").find("features.targets"), std::string::npos);
  EXPECT_NE(err("{targets: 3}").find("f.yaml"), std::string::npos);
  EXPECT_NE(err("{drop_probability: 1.5}").find("features.drop_probability"), std::string::npos);
  EXPECT_NE(err("{grid: [2.5, 3]}").find("features.grid"), std::string::npos);
  EXPECT_NE(err("{pixel_noise_sigma: -1}").find("features.pixel_noise_sigma"), std::string::npos);
}

}  // namespace
}  // namespace vid::sim
