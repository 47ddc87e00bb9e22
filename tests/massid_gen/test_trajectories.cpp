/// @file test_trajectories.cpp
/// @brief Reference trajectories: analytic derivatives match numeric ones, start at rest,
/// documented sizes and periods.
#include <gtest/gtest.h>

#include "massid/gen/reference_trajectory.h"

using vid::massid::gen::make_reference_trajectory;
using vid::massid::gen::TrajectorySettings;

namespace {
const std::vector<std::string> kNames = {"random", "loop", "lemniscate", "zigzag", "square"};
}

TEST(MassIdTrajectory, DerivativesMatchNumericDifferences) {
  const TrajectorySettings s;
  for (const auto& name : kNames) {
    const auto traj = make_reference_trajectory(name, s, 42);
    const double h = 1e-5;
    for (double t = 0.37; t < 25.0; t += 0.731) {
      const auto r = traj->at(t), rp = traj->at(t + h), rm = traj->at(t - h);
      EXPECT_LT(((rp.p_W - rm.p_W) / (2 * h) - r.v_W).norm(), 1e-6) << name << " t=" << t;
      EXPECT_LT(((rp.v_W - rm.v_W) / (2 * h) - r.a_W).norm(), 1e-6) << name << " t=" << t;
      EXPECT_LT(((rp.a_W - rm.a_W) / (2 * h) - r.j_W).norm(), 1e-5) << name << " t=" << t;
    }
  }
}

TEST(MassIdTrajectory, StartsAtRestAtTheDocumentedAltitude) {
  const TrajectorySettings s;
  for (const auto& name : kNames) {
    const auto r0 = make_reference_trajectory(name, s, 1)->at(0.0);
    EXPECT_LT(r0.v_W.norm(), 1e-12) << name;
    EXPECT_LT(r0.a_W.norm(), 1e-12) << name;
    const double dz = name == "zigzag" ? 0.5 * s.zigzag_dz_m : name == "random" ? s.random_amplitude_z : 0.0;
    EXPECT_NEAR(r0.p_W.z(), s.altitude_m, dz + 1e-9) << name;
  }
}

TEST(MassIdTrajectory, SizesAndPeriods) {
  const TrajectorySettings s;
  // loop: circle of the given radius, periodic after the ramp.
  const auto loop = make_reference_trajectory("loop", s, 0);
  for (double t = s.ramp_s; t < 20.0; t += 0.5) {
    const auto r = loop->at(t);
    EXPECT_NEAR(r.p_W.head<2>().norm(), s.loop_radius_m, 1e-9);
    EXPECT_LT((loop->at(t + s.loop_period_s).p_W - r.p_W).norm(), 1e-9);
    EXPECT_NEAR(r.v_W.head<2>().norm(), 2 * M_PI * s.loop_radius_m / s.loop_period_s, 1e-9);
  }
  // lemniscate: |x| <= A, |y| <= A/2, period T.
  const auto lem = make_reference_trajectory("lemniscate", s, 0);
  double x_max = 0, y_max = 0, a_max = 0;
  for (double t = s.ramp_s; t < s.ramp_s + s.lemniscate_period_s; t += 0.01) {
    const auto r = lem->at(t);
    x_max = std::max(x_max, std::abs(r.p_W.x()));
    y_max = std::max(y_max, std::abs(r.p_W.y()));
    a_max = std::max(a_max, r.a_W.head<2>().norm());
  }
  EXPECT_NEAR(x_max, s.lemniscate_size_m, 1e-3);
  EXPECT_NEAR(y_max, 0.5 * s.lemniscate_size_m, 1e-3);
  EXPECT_GT(a_max, 5.0);  // deliberately close to the 6 m/s^2 horizontal bound
  // square: rests at the corners of a side x side square.
  const auto sq = make_reference_trajectory("square", s, 0);
  const double half = 0.5 * s.square_side_m;
  for (int k = 1; k < 8; ++k) {
    const double t = 0.5 * s.ramp_s + k * s.square_leg_s;  // corners after the warp's offset
    const auto r = sq->at(t);
    EXPECT_NEAR(std::abs(r.p_W.x()), half, 1e-9);
    EXPECT_NEAR(std::abs(r.p_W.y()), half, 1e-9);
    EXPECT_LT(r.v_W.norm(), 1e-9);
  }
  // zigzag: lateral swing of dy at the corners.
  const auto zz = make_reference_trajectory("zigzag", s, 0);
  for (int k = 1; k < 8; ++k) {
    const auto r = zz->at(0.5 * s.ramp_s + k * s.zigzag_leg_s);
    EXPECT_NEAR(std::abs(r.p_W.y()), 0.5 * s.zigzag_dy_m, 1e-9);
    EXPECT_LT(r.v_W.norm(), 1e-9);
  }
}

TEST(MassIdTrajectory, RandomDependsOnSeedAndRespectsItsAccelerationBound) {
  const TrajectorySettings s;
  const auto a = make_reference_trajectory("random", s, 1);
  const auto b = make_reference_trajectory("random", s, 1);
  const auto c = make_reference_trajectory("random", s, 2);
  EXPECT_EQ(a->at(7.0).p_W, b->at(7.0).p_W);
  EXPECT_GT((a->at(7.0).p_W - c->at(7.0).p_W).norm(), 1e-3);
  for (std::uint64_t seed = 1; seed < 30; ++seed) {
    const auto tr = make_reference_trajectory("random", s, seed);
    for (double t = s.ramp_s; t < 25.0; t += 0.05) {
      const auto r = tr->at(t);
      EXPECT_LE(std::abs(r.a_W.x()), s.random_accel_xy + 1e-9);
      EXPECT_LE(std::abs(r.a_W.y()), s.random_accel_xy + 1e-9);
      EXPECT_LE(std::abs(r.a_W.z()), s.random_accel_z + 1e-9);
      EXPECT_LE(std::abs(r.p_W.x()), s.random_amplitude_xy + 1e-9);
      EXPECT_LE(std::abs(r.p_W.z() - s.altitude_m), s.random_amplitude_z + 1e-9);
    }
  }
  EXPECT_THROW(make_reference_trajectory("circle", s, 0), std::invalid_argument);
}
