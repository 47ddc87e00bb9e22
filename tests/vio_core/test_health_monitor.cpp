// HealthMonitor (vio_core/health_monitor.h): the chi2 gate's rejection fraction over a window
// and feature starvation, on hand-made frame statistics at 20 Hz.
#include <gtest/gtest.h>

#include "vio_core/health_monitor.h"

namespace vid {
namespace {

constexpr TimeNs kFrameNs = 50'000'000;  // 20 Hz

TEST(HealthMonitor, ConsistentFilterStaysHealthy) {
  HealthMonitor m{EstimatorParams{}};
  for (int k = 0; k < 400; ++k) {  // 20 s, 40 features tested per frame, 2-4 rejected (5-10 %)
    const HealthVerdict v = m.on_frame(k * kFrameNs, 40, 2 + k % 3);
    ASSERT_FALSE(v.out_of_band) << k;
    ASSERT_FALSE(v.starving) << k;
    ASSERT_TRUE(v.message.empty());
  }
  EXPECT_NEAR(m.max_rejected_fraction(), 3.0 / 40.0, 0.01);
  EXPECT_EQ(m.starvation_episodes(), 0);
}

TEST(HealthMonitor, InnovationsOutOfBandAfterTheWindowFills) {
  EstimatorParams p;  // window 1 s, >= 30 tested
  p.health_max_chi2_rejected_fraction = 0.5;
  HealthMonitor m{p};
  for (int k = 0; k < 40; ++k) ASSERT_FALSE(m.on_frame(k * kFrameNs, 40, 2).out_of_band);
  // From frame 40 on, 30 of 40 fail the gate: the window's fraction crosses 0.5 once more than
  // half of its 20 frames are bad (11 bad: (11*30 + 9*2) / 800 = 0.435; 14 bad: 0.545).
  int fired = -1;
  std::string message;
  for (int k = 40; k < 80 && fired < 0; ++k) {
    const HealthVerdict v = m.on_frame(k * kFrameNs, 40, 30);
    if (v.out_of_band) {
      fired = k;
      message = v.message;
    }
  }
  EXPECT_GE(fired, 40 + 12);
  EXPECT_LE(fired, 40 + 14);
  EXPECT_NE(message.find("failed the chi2 gate over the last 1 s"), std::string::npos) << message;
}

TEST(HealthMonitor, FewTestedFeaturesSayNothing) {
  HealthMonitor m{EstimatorParams{}};
  // 1 feature per frame, always rejected: 20 per window < 30.
  for (int k = 0; k < 100; ++k) ASSERT_FALSE(m.on_frame(k * kFrameNs, 1, 1).out_of_band) << k;
  EXPECT_EQ(m.max_rejected_fraction(), 0.0);
}

TEST(HealthMonitor, OffWhenTheFractionIsZero) {
  EstimatorParams p;
  p.health_max_chi2_rejected_fraction = 0.0;
  HealthMonitor m{p};
  for (int k = 0; k < 100; ++k) ASSERT_FALSE(m.on_frame(k * kFrameNs, 40, 40).out_of_band);
}

TEST(HealthMonitor, StarvationIsReportedCountedAndEnds) {
  HealthMonitor m{EstimatorParams{}};  // starving after 1 s without a feature used
  for (int k = 0; k < 20; ++k) ASSERT_FALSE(m.on_frame(k * kFrameNs, 40, 2).starving);
  // 2 s with frames but no feature used (tracks lost: blur, covered lens).
  int first_starving = -1;
  for (int k = 20; k < 60; ++k) {
    const HealthVerdict v = m.on_frame(k * kFrameNs, 0, 0);
    EXPECT_FALSE(v.out_of_band);
    if (v.starving && first_starving < 0) {
      first_starving = k;
      EXPECT_NE(v.message.find("feature starvation"), std::string::npos) << v.message;
    }
  }
  EXPECT_EQ(first_starving, 39);  // last use at frame 19, 1 s later
  EXPECT_TRUE(m.starving());
  EXPECT_FALSE(m.on_frame(60 * kFrameNs, 40, 2).starving);  // features again
  EXPECT_EQ(m.starvation_episodes(), 1);
  EXPECT_NEAR(m.starved_s(), 21 * 0.05, 1e-9);  // frames 39 .. 60
  for (int k = 61; k < 120; ++k) m.on_frame(k * kFrameNs, 0, 0);
  EXPECT_EQ(m.starvation_episodes(), 2);
}

TEST(HealthMonitor, StillCameraWithoutParallaxIsNotStarving) {
  HealthMonitor m{EstimatorParams{}};
  // Tracks reach the update every frame but none triangulates (no parallax): not starvation.
  for (int k = 0; k < 100; ++k) ASSERT_FALSE(m.on_frame(k * kFrameNs, 0, 0, 25).starving) << k;
  EXPECT_EQ(m.starvation_episodes(), 0);
}

}  // namespace
}  // namespace vid
