/// @file test_mass_profiles.cpp
/// @brief The five mass profiles at known times (no jitter), and jitter snapping to the grid.
#include <gtest/gtest.h>

#include <cmath>

#include "massid/gen/mass_profile.h"

using vid::massid::gen::MassProfile;
using vid::massid::gen::MassProfileSettings;

namespace {
MassProfileSettings no_jitter() {
  MassProfileSettings s;
  s.time_jitter_s = 0.0;
  return s;
}
}  // namespace

TEST(MassIdMassProfile, ValuesAtKnownTimes) {
  const MassProfileSettings s = no_jitter();
  const double m = 1.0;
  const auto constant = MassProfile::make("constant", m, s, 100, 1);
  EXPECT_EQ(constant.mass_kg(0.0), 1.0);
  EXPECT_EQ(constant.mass_kg(24.0), 1.0);

  // Spraying: 1.0 kg until 5 s, linear to 0.7 kg at 20 s, then constant.
  const auto spray = MassProfile::make("linear_decrease", m, s, 100, 1);
  EXPECT_DOUBLE_EQ(spray.mass_kg(4.0), 1.0);
  EXPECT_DOUBLE_EQ(spray.mass_kg(5.0), 1.0);
  EXPECT_NEAR(spray.mass_kg(12.5), 0.85, 1e-12);
  EXPECT_NEAR(spray.mass_kg(20.0), 0.7, 1e-12);
  EXPECT_NEAR(spray.mass_kg(24.0), 0.7, 1e-12);

  // Drop of 25 % at 10 s, right-continuous.
  const auto drop = MassProfile::make("step_drop", m, s, 100, 1);
  EXPECT_EQ(drop.mass_kg(9.99), 1.0);
  EXPECT_EQ(drop.mass_kg(10.0), 0.75);
  EXPECT_EQ(drop.mass_kg(20.0), 0.75);
  const auto pick = MassProfile::make("step_pickup", m, s, 100, 1);
  EXPECT_EQ(pick.mass_kg(9.99), 1.0);
  EXPECT_EQ(pick.mass_kg(10.0), 1.25);

  // Up and down: +25 % on [5, 10) and [15, 20).
  const auto ud = MassProfile::make("up_down", m, s, 100, 1);
  const std::vector<std::pair<double, double>> expect = {
      {0.0, 1.0}, {4.99, 1.0}, {5.0, 1.25}, {9.99, 1.25}, {10.0, 1.0},
      {14.0, 1.0}, {15.0, 1.25}, {19.5, 1.25}, {20.0, 1.0}, {25.0, 1.0}};
  for (const auto& [t, mt] : expect) EXPECT_EQ(ud.mass_kg(t), mt) << "t=" << t;
  EXPECT_THROW(MassProfile::make("leaking", m, s, 100, 1), std::invalid_argument);
}

TEST(MassIdMassProfile, JitterMovesAllEventsTogetherOntoTheSampleGrid) {
  const MassProfileSettings s;  // +-1 s jitter
  bool saw_shift = false;
  for (std::uint64_t seed = 1; seed < 20; ++seed) {
    const auto ud = MassProfile::make("up_down", 2.0, s, 100, seed);
    const auto& ev = ud.event_times();
    ASSERT_EQ(ev.size(), 4u);
    const double shift = ev[0] - 5.0;
    EXPECT_LE(std::abs(shift), s.time_jitter_s + 0.005);
    if (std::abs(shift) > 0.05) saw_shift = true;
    for (size_t i = 0; i < ev.size(); ++i) {
      EXPECT_NEAR(ev[i] - s.up_down_times_s[i], shift, 1e-9);
      EXPECT_NEAR(ev[i] * 100.0, std::round(ev[i] * 100.0), 1e-9);  // on the 100 Hz grid
      const double t_grid = std::round(ev[i] * 100.0) / 100.0;
      EXPECT_EQ(ud.mass_kg(t_grid), i % 2 == 0 ? 2.5 : 2.0);
    }
  }
  EXPECT_TRUE(saw_shift);
}
