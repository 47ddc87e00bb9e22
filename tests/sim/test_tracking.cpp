/// @file test_tracking.cpp
/// @brief Controller tracking RMSE < 0.05 m on loop, lemniscate, square, zigzag and random at
/// nominal speed (max_speed 1 m/s, max_accel 1.5 m/s^2), with and without the rope, on the
/// vid17_like vehicle (noise off; the controller sees the true state).

#include <gtest/gtest.h>

#include <cmath>

#include "sim_test_util.h"

namespace vid::sim::test {
namespace {

struct Case {
  std::string type;
  bool rope;
};

class Tracking : public ::testing::TestWithParam<Case> {};

TEST_P(Tracking, RmseBelow5cm) {
  const Case c = GetParam();
  Scenario sc = load_scenario(preset_path("vid17_like"));
  sc.duration_s = 30.0;
  sc.noise = false;
  sc.cameras.cameras.clear();
  TrajectoryConfig& t = sc.trajectory;
  t.type = c.type;
  t.duration_s = sc.duration_s;
  t.center = Eigen::Vector3d(0.0, 0.0, 1.3);
  t.radius_m = 1.2;
  t.max_speed = 1.0;
  t.max_accel = 1.5;
  t.yaw_mode = c.type == "circle" ? YawMode::kFollow : YawMode::kFixed;
  sc.environment.rope.enabled = c.rope;
  Simulator sim(sc);
  Recording rec;
  sim.run(rec);
  double vmax = 0.0, amax = 0.0;
  // Over the designed motion (the random spline is longer than the run).
  const double t_end = std::isfinite(sim.trajectory().duration_s()) ? sim.trajectory().duration_s() : sc.duration_s;
  trajectory_extremes(sim.trajectory(), 0.0, t_end, 0.01, &vmax, &amax);
  EXPECT_GT(std::max(vmax / t.max_speed, amax / t.max_accel), 0.95) << "not at nominal speed";
  // The rope must actually pull in the rope cases.
  double max_force = 0.0;
  for (const auto& f : rec.force) max_force = std::max(max_force, f.f_W_N.norm());
  if (c.rope) {
    EXPECT_GT(max_force, 2.0);
  }
  const double rmse = tracking_rmse(sim, rec, 0.0);
  std::printf("[%s rope=%d] tracking RMSE %.4f m, max speed %.2f m/s, max |F_ext| %.2f N\n", c.type.c_str(),
              c.rope, rmse, vmax, max_force);
  EXPECT_LT(rmse, 0.05);
}

INSTANTIATE_TEST_SUITE_P(
    All, Tracking,
    ::testing::Values(Case{"circle", false}, Case{"circle", true}, Case{"lemniscate", false}, Case{"lemniscate", true},
                      Case{"square", false}, Case{"square", true}, Case{"zigzag", false}, Case{"zigzag", true},
                      Case{"random", false}, Case{"random", true}),
    [](const auto& info) { return info.param.type + (info.param.rope ? "_rope" : "_free"); });

TEST(Tracking, CircleWithFixedYaw) {
  Scenario sc = load_scenario(preset_path("vid_loaded"));
  sc.noise = false;
  sc.duration_s = 20.0;
  sc.environment.payloads.clear();
  Recording rec = record(sc);
  Simulator sim(sc);
  EXPECT_LT(tracking_rmse(sim, rec, 0.0), 0.05);
}

TEST(Tracking, EveryPresetTracksItsReference) {
  for (const std::string name : {"vid17_like_short", "vid18_like_short", "vid_loaded_short", "euroc_like_short", "hover",
                                 "fast_yaw", "checkerboard", "wind_gusts", "spraying"}) {
    Scenario sc = load_scenario(preset_path(name));
    sc.noise = false;
    sc.duration_s = std::min(sc.duration_s, 30.0);
    sc.trajectory.duration_s = sc.duration_s;
    const Recording rec = record(sc);
    Simulator sim(sc);
    const double rmse = tracking_rmse(sim, rec, 0.0);
    std::printf("[%s] tracking RMSE %.4f m\n", name.c_str(), rmse);
    EXPECT_LT(rmse, 0.05) << name;
  }
}

}  // namespace
}  // namespace vid::sim::test
