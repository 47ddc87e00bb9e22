// Scene: config parsing (strict keys, errors naming file and key), geometry queries,
// textures, determinism.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>

#include "io/errors.h"
#include "sim/render/scene.h"

namespace vid::sim {
namespace {

SceneConfig small_config(std::uint64_t seed = 3) {
  SceneConfig c;
  c.room_size = Eigen::Vector3d(6.0, 5.0, 3.0);
  c.room_center = Eigen::Vector3d(0.0, 0.0, 1.5);
  c.texture_seed = seed;
  c.texels_per_m = 120;
  c.boxes.count = 5;
  c.boxes.size_min = 0.3;
  c.boxes.size_max = 0.8;
  return c;
}

std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("vid_sim_render_" + name);
  std::ofstream(path) << text;
  return path.string();
}

std::string error_of(const std::string& yaml_text) {
  try {
    parse_scene_config(YAML::Load(yaml_text), "scn.yaml");
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneConfig, ParsesAllKeys) {
  const SceneConfig c = parse_scene_config(YAML::Load(R"(
room_size: [10, 8, 3.5]
room_center: [1, 0, 1.75]
texture_seed: 42
texels_per_m: 150
boxes: {count: 3, size_min: 0.2, size_max: 0.5, keep_out_min: [-1, -1, 0], keep_out_max: [1, 1, 3]}
checkerboard: {wall: -y, center: [0.5, 1.2], squares: [7, 5], square_size: 0.1}
)"), "scn.yaml");
  EXPECT_EQ(c.room_size, Eigen::Vector3d(10, 8, 3.5));
  EXPECT_EQ(c.room_center, Eigen::Vector3d(1, 0, 1.75));
  EXPECT_EQ(c.texture_seed, 42u);
  EXPECT_EQ(c.texels_per_m, 150);
  EXPECT_EQ(c.boxes.count, 3);
  EXPECT_TRUE(c.boxes.has_keep_out);
  EXPECT_EQ(c.boxes.keep_out_max, Eigen::Vector3d(1, 1, 3));
  EXPECT_TRUE(c.checkerboard.enabled);
  EXPECT_EQ(c.checkerboard.wall, "-y");
  EXPECT_EQ(c.checkerboard.squares_x, 7);
  EXPECT_EQ(c.checkerboard.squares_y, 5);
  EXPECT_DOUBLE_EQ(c.checkerboard.square_size, 0.1);
}

TEST(SceneConfig, ErrorsNameFileAndKey) {
  const std::string unknown = error_of("room_size: [5, 5, 3]\nroom_sise: 3\n");
  EXPECT_NE(unknown.find("scn.yaml"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("scene.room_sise"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown key"), std::string::npos) << unknown;
  EXPECT_NE(error_of("boxes: {count: 2, colour: red}").find("scene.boxes.colour"), std::string::npos);
  EXPECT_NE(error_of("checkerboard: {wall: +z}").find("scene.checkerboard.wall"), std::string::npos);
  EXPECT_NE(error_of("room_size: [5, 5]").find("scene.room_size"), std::string::npos);
  EXPECT_NE(error_of("room_size: [5, -1, 3]").find("scene.room_size"), std::string::npos);
  EXPECT_NE(error_of("texture_seed: abc").find("scene.texture_seed"), std::string::npos);
  EXPECT_NE(error_of("boxes: {size_min: 0.5, size_max: 0.2}").find("scene.boxes.size_min"),
            std::string::npos);
  EXPECT_NE(error_of("checkerboard: {center: [0, 9.0]}").find("scene.checkerboard.center"),
            std::string::npos);
  EXPECT_NE(error_of("boxes: {keep_out_min: [0, 0, 0]}").find("keep_out"), std::string::npos);
  EXPECT_EQ(error_of("texture_seed: 5"), "");
}

TEST(SceneConfig, FromScenarioFile) {
  const std::string good = write_temp("good.yaml",
                                      "name: x\nscene:\n  room_size: [6, 5, 3]\n  texture_seed: 4\n"
                                      "  texels_per_m: 100\n  boxes: {count: 2}\n");
  const SceneConfig c = scene_config_from_scenario_file(good);
  EXPECT_EQ(c.room_size, Eigen::Vector3d(6, 5, 3));
  EXPECT_EQ(c.texture_seed, 4u);
  const Scene s = scene_from_scenario_file(good);
  EXPECT_EQ(s.config().boxes.count, 2);
  const std::string bad = write_temp("bad.yaml", "scene:\n  room_size: [6, 5, 3]\n  walls: 4\n");
  try {
    scene_config_from_scenario_file(bad);
    FAIL() << "no error";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("scene.walls"), std::string::npos) << e.what();
  }
  EXPECT_THROW(scene_config_from_scenario_file("/nonexistent/scenario.yaml"), io::ConfigError);
}

TEST(Scene, RaycastHitsWallsAndBoxes) {
  SceneConfig c = small_config();
  c.boxes.count = 0;
  const Scene empty(c);
  const Eigen::Vector3d o(0.5, -0.5, 1.0);
  // Straight at the +x wall (x = 3) and the floor (z = 0).
  auto p = empty.raycast(o, Eigen::Vector3d(2.0, 0.0, 0.0));
  ASSERT_TRUE(p);
  EXPECT_NEAR((*p - Eigen::Vector3d(3.0, -0.5, 1.0)).norm(), 0.0, 1e-12);
  auto h = empty.intersect(o, Eigen::Vector3d(0.3, 0.2, -1.0));
  ASSERT_TRUE(h);
  EXPECT_EQ(h->surface, 4);  // floor = 2 * z + min side
  EXPECT_DOUBLE_EQ(h->p_W.z(), 0.0);
  EXPECT_NEAR(h->p_W.x(), 0.5 + 0.3, 1e-12);
  EXPECT_EQ(h->normal_W, Eigen::Vector3d(0, 0, 1));

  // With boxes: a ray towards a box centre from the room centre hits that box (first),
  // never further than the box centre, and on its surface.
  const Scene s(small_config());
  ASSERT_GT(s.boxes().size(), 0u);
  const Eigen::Vector3d from = s.config().room_center;
  ASSERT_TRUE(s.is_free(from));
  for (std::size_t b = 0; b < s.boxes().size(); ++b) {
    const Box& box = s.boxes()[b];
    const Eigen::Vector3d c_W = 0.5 * (box.min_W + box.max_W);
    const auto hit = s.intersect(from, c_W - from);
    ASSERT_TRUE(hit);
    EXPECT_LT(hit->t, 1.0);
    EXPECT_FALSE(s.is_free(hit->p_W + 1e-6 * (c_W - from).normalized()));
    const bool on_box = hit->surface >= 6;
    EXPECT_TRUE(on_box || !s.is_free(c_W));
  }
}

TEST(Scene, BoxesRespectKeepOutAndRoom) {
  SceneConfig c = small_config();
  c.boxes.count = 12;
  c.boxes.has_keep_out = true;
  c.boxes.keep_out_min = Eigen::Vector3d(-1.5, -1.0, -1.0);
  c.boxes.keep_out_max = Eigen::Vector3d(1.5, 1.0, 5.0);
  const Scene s(c);
  EXPECT_GE(s.boxes().size(), 6u);
  for (const Box& b : s.boxes()) {
    EXPECT_TRUE((b.min_W.array() >= s.room_min().array() - 1e-12).all());
    EXPECT_TRUE((b.max_W.array() <= s.room_max().array() + 1e-12).all());
    const bool overlap = (b.min_W.array() < c.boxes.keep_out_max.array()).all() &&
                         (b.max_W.array() > c.boxes.keep_out_min.array()).all();
    EXPECT_FALSE(overlap);
  }
}

TEST(Scene, DeterministicAndSeedDependent) {
  const Scene a(small_config(7)), b(small_config(7)), other(small_config(8));
  ASSERT_EQ(a.surfaces().size(), b.surfaces().size());
  for (std::size_t i = 0; i < a.surfaces().size(); ++i) {
    EXPECT_EQ(cv::norm(a.surfaces()[i].texture, b.surfaces()[i].texture, cv::NORM_INF), 0.0);
  }
  EXPECT_GT(cv::norm(a.surfaces()[0].texture, other.surfaces()[0].texture, cv::NORM_L1), 0.0);
}

TEST(Scene, TexturesDifferPerSurfaceAndHaveContrast) {
  const Scene s(small_config());
  const auto& surf = s.surfaces();
  for (std::size_t i = 0; i < surf.size(); ++i) {
    cv::Scalar mean, stddev;
    cv::meanStdDev(surf[i].texture, mean, stddev);
    EXPECT_GT(stddev[0], 25.0) << "surface " << i;
    // Different content on every surface: compare the common top-left corner area.
    for (std::size_t j = 0; j < i; ++j) {
      const int w = std::min(surf[i].texture.cols, surf[j].texture.cols);
      const int h = std::min(surf[i].texture.rows, surf[j].texture.rows);
      const cv::Rect r(0, 0, w, h);
      EXPECT_GT(cv::norm(surf[i].texture(r), surf[j].texture(r), cv::NORM_L1) / (w * h), 10.0)
          << i << " vs " << j;
    }
  }
}

TEST(Scene, CheckerboardCornersLieOnWallAtSquareSpacing) {
  SceneConfig c = small_config();
  c.checkerboard.enabled = true;
  c.checkerboard.wall = "-y";
  c.checkerboard.center = Eigen::Vector2d(0.5, 1.4);
  const Scene s(c);
  const auto corners = s.checkerboard_corners_W();
  ASSERT_EQ(corners.size(), static_cast<std::size_t>((c.checkerboard.squares_x - 1) *
                                                     (c.checkerboard.squares_y - 1)));
  EXPECT_EQ(s.checkerboard_surface(), 2);  // -y wall
  for (const auto& p : corners) EXPECT_DOUBLE_EQ(p.y(), s.room_min().y());
  EXPECT_NEAR((corners[1] - corners[0]).norm(), c.checkerboard.square_size, 1e-12);
  // Centre of the inner-corner grid = the board centre.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : corners) mean += p / static_cast<double>(corners.size());
  EXPECT_NEAR(mean.x(), 0.5, 1e-12);
  EXPECT_NEAR(mean.z(), 1.4, 1e-12);
  // The pattern alternates across a corner: the four neighbouring squares are dark/light.
  const Surface& w = s.surfaces()[s.checkerboard_surface()];
  const double e = 0.25 * c.checkerboard.square_size;
  const Eigen::Vector3d q = corners[10];
  const double u = q[w.u_axis] - w.u0, v = q[w.v_axis] - w.v0;
  const float a = s.shade(2, u - e, v - e), b = s.shade(2, u + e, v - e);
  const float d = s.shade(2, u + e, v + e), f = s.shade(2, u - e, v + e);
  EXPECT_EQ(a, d);
  EXPECT_EQ(b, f);
  EXPECT_NE(a, b);
}

}  // namespace
}  // namespace vid::sim
