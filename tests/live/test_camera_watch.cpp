// CameraWatch (vid_live's no_camera fault, issue #52): the bound is data time of IMU, a frame
// ends the fault, an input without a frame is reported once, at the bound or at its end.
#include <gtest/gtest.h>

#include "live/camera_watch.h"

using vid::live::CameraWatch;

namespace {
constexpr vid::TimeNs kMs = 1'000'000;
}

TEST(CameraWatch, NoFrameWithinTheBoundIsAFaultReportedOnce) {
  CameraWatch w(2.0);
  const vid::TimeNs t0 = 1'000'000'000'000;
  for (vid::TimeNs t = t0; t <= t0 + 2000 * kMs; t += 5 * kMs) EXPECT_FALSE(w.on_imu(t)) << t - t0;
  EXPECT_FALSE(w.fault());
  EXPECT_TRUE(w.on_imu(t0 + 2005 * kMs));  // past 2 s of IMU data: once
  EXPECT_TRUE(w.fault());
  EXPECT_FALSE(w.on_imu(t0 + 3000 * kMs));
  EXPECT_FALSE(w.on_end());  // already reported
  EXPECT_TRUE(w.never_delivered() && w.fault());
  EXPECT_FALSE(w.first_frame_after_s().has_value());
}

TEST(CameraWatch, ALateCameraEndsTheFault) {
  CameraWatch w(1.0);
  const vid::TimeNs t0 = 5 * kMs;
  for (vid::TimeNs t = t0; t <= t0 + 1500 * kMs; t += 5 * kMs) w.on_imu(t);
  EXPECT_TRUE(w.fault());
  EXPECT_TRUE(w.on_frame(t0 + 1500 * kMs));
  EXPECT_FALSE(w.fault());
  EXPECT_FALSE(w.never_delivered());
  EXPECT_FALSE(w.on_end());
  EXPECT_DOUBLE_EQ(*w.first_frame_after_s(), 1.5);
}

TEST(CameraWatch, AShortInputWithoutFrameIsReportedAtItsEnd) {
  CameraWatch w(3.0);
  for (vid::TimeNs t = 0; t <= 1000 * kMs; t += 5 * kMs) EXPECT_FALSE(w.on_imu(t));
  EXPECT_TRUE(w.on_end());
  EXPECT_TRUE(w.fault());
  EXPECT_NEAR(w.imu_span_s(), 1.0, 1e-12);
}

TEST(CameraWatch, FramesBeforeTheBoundAreNoFault) {
  CameraWatch w(3.0);
  w.on_imu(0);
  EXPECT_FALSE(w.on_frame(100 * kMs));
  for (vid::TimeNs t = 0; t <= 10'000 * kMs; t += 5 * kMs) EXPECT_FALSE(w.on_imu(t));
  EXPECT_FALSE(w.on_end());
  EXPECT_FALSE(w.fault());
}

TEST(CameraWatch, NoImuNoFault) {  // nothing came at all: not this fault (the input is empty)
  CameraWatch w(3.0);
  EXPECT_FALSE(w.on_end());
  EXPECT_FALSE(w.fault());
}
