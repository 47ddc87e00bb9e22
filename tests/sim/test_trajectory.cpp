/// @file test_trajectory.cpp
/// @brief Reference trajectories: derivatives agree with numeric differentiation, limits hold,
/// the start is at rest, TUM file fit.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "sim/trajectory.h"

namespace vid::sim {
namespace {

TrajectoryConfig config(const std::string& type) {
  TrajectoryConfig c;
  c.type = type;
  c.radius_m = 1.2;
  c.max_speed = 1.0;
  c.max_accel = 1.5;
  c.duration_s = 40.0;
  c.seed = 3;
  c.random_yaw_amplitude = 0.5;
  if (type == "circle") c.yaw_mode = YawMode::kFollow;
  if (type == "vertical_steps") c.step_heights_m = {2.2, 0.7, 1.8};
  return c;
}

void check_derivatives(const Trajectory& tr, double t0, double t1) {
  const double h = 1e-4;
  for (double t = t0; t < t1; t += 0.37) {
    const FlatOutput m = tr.eval(t - h), o = tr.eval(t), p = tr.eval(t + h);
    const double scale = 1.0 + o.v.norm() + o.a.norm() + o.j.norm() + o.s.norm();
    EXPECT_LT(((p.p - m.p) / (2 * h) - o.v).norm(), 1e-5 * scale) << "t=" << t;
    EXPECT_LT(((p.v - m.v) / (2 * h) - o.a).norm(), 1e-5 * scale) << "t=" << t;
    EXPECT_LT(((p.a - m.a) / (2 * h) - o.j).norm(), 1e-4 * scale) << "t=" << t;
    EXPECT_LT(((p.j - m.j) / (2 * h) - o.s).norm(), 1e-3 * scale) << "t=" << t;
    EXPECT_NEAR((p.yaw - m.yaw) / (2 * h), o.yaw_rate, 1e-5 * scale) << "t=" << t;
    EXPECT_NEAR((p.yaw_rate - m.yaw_rate) / (2 * h), o.yaw_acc, 1e-4 * scale) << "t=" << t;
  }
}

class TrajectoryTypes : public ::testing::TestWithParam<std::string> {};

TEST_P(TrajectoryTypes, DerivativesLimitsAndRest) {
  const auto tr = make_trajectory(config(GetParam()));
  // Square, zigzag and vertical steps have snap jumps at corners: central differences are
  // checked away from them.
  if (GetParam() != "square" && GetParam() != "zigzag" && GetParam() != "vertical_steps") {
    check_derivatives(*tr, 0.05, 30.0);
  }
  double vmax, amax;
  // Over the whole designed motion (the random spline covers 600 s whatever the run length).
  const double t_end = std::isfinite(tr->duration_s()) ? tr->duration_s() : 40.0;
  trajectory_extremes(*tr, 0.0, t_end, 0.005, &vmax, &amax);
  EXPECT_LE(vmax, 1.0 * 1.001);
  EXPECT_LE(amax, 1.5 * 1.001);
  if (GetParam() != "hover") {
    EXPECT_GT(std::max(vmax / 1.0, amax / 1.5), 0.9) << "nominal speed not reached";
  }
  const FlatOutput s = tr->eval(0.0);
  EXPECT_LT(s.v.norm() + s.a.norm() + s.j.norm(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(All, TrajectoryTypes,
                         ::testing::Values("hover", "circle", "lemniscate", "square", "zigzag", "vertical_steps",
                                           "random"));

TEST(Trajectory, VerticalStepsRestAtEachLevelAndRepeat) {
  TrajectoryConfig c = config("vertical_steps");
  c.hold_s = 0.5;
  c.start_delay_s = 2.0;
  const auto tr = make_trajectory(c);
  // Levels centre -> 2.2 -> 0.7 -> 1.8 -> centre, each reached at rest and held hold_s, straight
  // above the centre; the moves are what the thrust fit needs (vertical acceleration only).
  double t = c.start_delay_s;
  for (const double z : {2.2, 0.7, 1.8, c.center.z(), 2.2}) {
    double prev = t;
    while (std::abs(tr->eval(t).p.z() - z) > 1e-12 && t < prev + 10.0) t += 1e-3;
    ASSERT_LT(t, prev + 10.0) << "level " << z << " not reached";
    for (const double dt : {0.01, 0.25, 0.49}) {  // found within the last ms of the move
      const FlatOutput o = tr->eval(t + dt);
      EXPECT_NEAR(o.p.z(), z, 1e-12);
      EXPECT_LT(o.v.norm() + o.a.norm(), 1e-9);
      EXPECT_NEAR(o.p.x(), c.center.x(), 1e-12);
      EXPECT_NEAR(o.p.y(), c.center.y(), 1e-12);
    }
    t += 0.5;
  }
  c.step_heights_m = {2.2, 2.2};
  EXPECT_THROW(make_trajectory(c), std::invalid_argument);  // no move between two levels
  c.step_heights_m = {};
  EXPECT_THROW(make_trajectory(c), std::invalid_argument);
}

TEST(Trajectory, RandomStaysInBoxAndDependsOnSeed) {
  TrajectoryConfig c = config("random");
  const auto a = make_trajectory(c);
  c.seed = 4;
  const auto b = make_trajectory(c);
  double diff = 0.0;
  for (double t = 0; t < 40; t += 0.1) {
    const Eigen::Vector3d p = a->eval(t).p;
    EXPECT_TRUE((p.array() >= c.box_min.array() - 1e-9).all() && (p.array() <= c.box_max.array() + 1e-9).all());
    diff = std::max(diff, (p - b->eval(t).p).norm());
  }
  EXPECT_GT(diff, 0.3);
}

TEST(Trajectory, FileFitFollowsTumPoses) {
  const auto path = std::filesystem::temp_directory_path() / "vid_sim_test_traj.tum";
  {
    std::ofstream f(path);
    f << "# t x y z qx qy qz qw\n";
    for (int i = 0; i <= 400; ++i) {
      const double t = 100.0 + 0.05 * i;
      const double yaw = 0.3 * std::sin(0.5 * (t - 100));
      f << t << " " << std::cos(0.4 * (t - 100)) << " " << std::sin(0.4 * (t - 100)) << " " << 1.0 + 0.1 * (t - 100) / 20
        << " 0 0 " << std::sin(yaw / 2) << " " << std::cos(yaw / 2) << "\n";
    }
  }
  TrajectoryConfig c = config("file");
  c.file = path.string();
  c.max_speed = 2.0;
  c.max_accel = 3.0;
  const auto tr = make_trajectory(c);
  for (double t = 1.0; t < 19.0; t += 0.5) {
    const FlatOutput o = tr->eval(t);
    EXPECT_NEAR(o.p.x(), std::cos(0.4 * t), 2e-3);
    EXPECT_NEAR(o.p.y(), std::sin(0.4 * t), 2e-3);
    EXPECT_NEAR(o.yaw, 0.3 * std::sin(0.5 * t), 2e-3);
    EXPECT_NEAR(o.v.y(), 0.4 * std::cos(0.4 * t), 5e-3);
  }
  check_derivatives(*tr, 0.5, 19.0);
  std::filesystem::remove(path);
}

TEST(Trajectory, BadTumRowNamesFileLineAndField) {
  const auto path = std::filesystem::temp_directory_path() / "vid_sim_test_bad.tum";
  {
    std::ofstream f(path);
    f << "# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n0.1 0 zero 0 0 0 0 1\n";
  }
  TrajectoryConfig c = config("file");
  c.file = path.string();
  try {
    make_trajectory(c);
    FAIL() << "bad TUM row accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ":3: column 3 'y': expected a number, got 'zero'"),
              std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(Trajectory, UnknownTypeThrows) { EXPECT_THROW(make_trajectory(config("spiral")), std::invalid_argument); }

}  // namespace
}  // namespace vid::sim
