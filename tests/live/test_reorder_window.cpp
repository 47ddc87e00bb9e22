// The reorder window: ordering across streams, fault classification.
#include <gtest/gtest.h>

#include "live/reorder_window.h"

namespace vid::live {
namespace {

constexpr TimeNs kMs = 1'000'000;

LiveItem imu(TimeNs t) {
  LiveItem it;
  it.stream = Stream::kImu;
  it.t_ns = t;
  ImuSample s;
  s.t_ns = t;
  it.data = s;
  return it;
}
LiveItem cam(TimeNs t, int id) {
  LiveItem it;
  it.stream = id == 0 ? Stream::kCam0 : Stream::kCam1;
  it.t_ns = t;
  it.data = CameraImage{t, id, {}};
  return it;
}
std::vector<std::pair<TimeNs, Stream>> keys(const std::vector<LiveItem>& v) {
  std::vector<std::pair<TimeNs, Stream>> k;
  for (const auto& i : v) k.emplace_back(i.t_ns, i.stream);
  return k;
}

TEST(ReorderWindow, ReleasesInTimeThenStreamOrderOnceTheWindowHasPassed) {
  ReorderWindow w(10 * kMs);
  EXPECT_TRUE(w.insert(cam(10 * kMs, 1)));
  EXPECT_TRUE(w.insert(cam(10 * kMs, 0)));
  EXPECT_TRUE(w.insert(imu(10 * kMs)));
  EXPECT_TRUE(w.insert(imu(5 * kMs)));  // arrives after a later message
  EXPECT_TRUE(w.pop_ready().empty());   // newest 10 ms: nothing is 10 ms old yet
  EXPECT_TRUE(w.insert(imu(15 * kMs)));
  // Release to 5 ms.
  EXPECT_EQ(keys(w.pop_ready()), (std::vector<std::pair<TimeNs, Stream>>{{5 * kMs, Stream::kImu}}));
  EXPECT_TRUE(w.insert(imu(20 * kMs)));
  // Same timestamp: IMU first, then cam0, cam1 (the dataset reader's tie order).
  EXPECT_EQ(keys(w.pop_ready()), (std::vector<std::pair<TimeNs, Stream>>{
                                      {10 * kMs, Stream::kImu}, {10 * kMs, Stream::kCam0}, {10 * kMs, Stream::kCam1}}));
  EXPECT_EQ(keys(w.flush()), (std::vector<std::pair<TimeNs, Stream>>{{15 * kMs, Stream::kImu}, {20 * kMs, Stream::kImu}}));
  EXPECT_EQ(w.counters(Stream::kImu).reordered, 1);
  EXPECT_EQ(w.counters(Stream::kImu).received, 4);
  EXPECT_EQ(w.held(), 0u);
}

TEST(ReorderWindow, DuplicatesHeldOrReleasedAreDropped) {
  ReorderWindow w(5 * kMs);
  EXPECT_TRUE(w.insert(imu(1 * kMs)));
  EXPECT_FALSE(w.insert(imu(1 * kMs)));  // still held
  EXPECT_TRUE(w.insert(imu(10 * kMs)));
  EXPECT_EQ(w.pop_ready().size(), 1u);
  EXPECT_FALSE(w.insert(imu(1 * kMs)));  // already released
  EXPECT_EQ(w.counters(Stream::kImu).duplicate, 2);
  EXPECT_EQ(w.counters(Stream::kImu).late, 0);
  EXPECT_EQ(w.counters(Stream::kImu).received, 2);
}

TEST(ReorderWindow, MessagesOlderThanTheReleasePointAreLate) {
  ReorderWindow w(5 * kMs);
  EXPECT_TRUE(w.insert(imu(10 * kMs)));
  EXPECT_TRUE(w.insert(imu(20 * kMs)));
  EXPECT_EQ(w.pop_ready().size(), 1u);  // 10 ms released
  EXPECT_FALSE(w.insert(imu(8 * kMs)));  // behind what was processed
  EXPECT_EQ(w.counters(Stream::kImu).late, 1);
  // A camera image at 12 ms is still in time (after the released 10 ms), one at 10 ms too (the
  // IMU comes first at equal times), one at 9 ms is behind the released IMU: late.
  EXPECT_TRUE(w.insert(cam(12 * kMs, 0)));
  EXPECT_TRUE(w.insert(cam(10 * kMs, 0)));
  EXPECT_EQ(w.counters(Stream::kCam0).reordered, 2);
  EXPECT_FALSE(w.insert(cam(9 * kMs, 0)));
  EXPECT_EQ(w.counters(Stream::kCam0).late, 1);
}

TEST(ReorderWindow, ImageSentLateBeforeACameraStallIsLate) {
  // The soak's case: the last image before a camera stall is sent 100 ms late while the IMU
  // keeps flowing. No later image exists, but the IMU past it was released: it is late, and
  // what is released stays in time order.
  ReorderWindow w(30 * kMs);
  std::vector<LiveItem> released;
  auto take = [&] {
    for (auto& it : w.pop_ready()) released.push_back(std::move(it));
  };
  for (TimeNs t = 0; t <= 200 * kMs; t += 5 * kMs) {
    EXPECT_TRUE(w.insert(imu(t)));
    if (t == 50 * kMs) {
      EXPECT_TRUE(w.insert(cam(t, 0)));  // the image before the stall; 67 ms is held back
    }
    if (t == 165 * kMs) {
      EXPECT_FALSE(w.insert(cam(67 * kMs, 0)));  // arrives ~100 ms late
    }
    take();
  }
  for (auto& it : w.flush()) released.push_back(std::move(it));
  EXPECT_EQ(w.counters(Stream::kCam0).late, 1);
  EXPECT_EQ(w.counters(Stream::kCam0).reordered, 0);
  for (std::size_t i = 1; i < released.size(); ++i)
    EXPECT_LE(std::make_tuple(released[i - 1].t_ns, static_cast<int>(released[i - 1].stream)),
              std::make_tuple(released[i].t_ns, static_cast<int>(released[i].stream)));
}

TEST(ReorderWindow, GapsCountMissingMessagesFromTheLearntPeriod) {
  ReorderWindow w(0);
  const TimeNs period = 33'333'333;
  // Frames 0..19 with 5, 6 and 12 missing.
  for (int k = 0; k < 20; ++k) {
    if (k == 5 || k == 6 || k == 12) continue;
    EXPECT_TRUE(w.insert(cam(k * period + (k % 3), 0)));  // a few ns of jitter
  }
  w.flush();
  EXPECT_EQ(w.counters(Stream::kCam0).missing, 3);
  EXPECT_EQ(w.counters(Stream::kCam0).received, 17);
}

TEST(ReorderWindow, MalformedIsCountedPerStream) {
  ReorderWindow w(0);
  w.count_malformed(Stream::kRotor);
  w.count_malformed(Stream::kRotor);
  EXPECT_EQ(w.counters(Stream::kRotor).malformed, 2);
  EXPECT_EQ(w.counters(Stream::kImu).malformed, 0);
}

}  // namespace
}  // namespace vid::live
