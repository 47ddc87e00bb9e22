// scan_lcm_log on damaged event logs whose event numbers are garbage (fuzz_lcm found a signed
// overflow in the gap computation: numbers -9.15e18 then 7.2e16 around a damaged span).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "live/lcm_input.h"

namespace vid::live {
namespace {

namespace fs = std::filesystem;

void put_be(std::vector<std::uint8_t>* b, std::uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) b->push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// One LCM event (sync word, number, timestamp, channel, 2 data bytes).
void put_event(std::vector<std::uint8_t>* b, std::int64_t number) {
  put_be(b, 0xEDA1DA01u, 4);
  put_be(b, static_cast<std::uint64_t>(number), 8);
  put_be(b, 1000, 8);
  put_be(b, 2, 4);
  put_be(b, 2, 4);
  b->insert(b->end(), {'C', 'H', 0, 0});
}

/// A log of events with @p numbers, three garbage bytes between consecutive events.
std::string write_log(const std::vector<std::int64_t>& numbers, const std::string& name) {
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    if (i > 0) bytes.insert(bytes.end(), {0x11, 0x22, 0x33});
    put_event(&bytes, numbers[i]);
  }
  const fs::path path = fs::path(::testing::TempDir()) / name;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

TEST(LcmLogScan, GapsBetweenEventNumbersAreCounted) {
  const LogScan s = scan_lcm_log(write_log({0, 1, 5}, "gaps.lcm"));
  EXPECT_EQ(s.events, 3u);
  ASSERT_EQ(s.damaged.size(), 2u);
  EXPECT_EQ(s.damaged[0].events_lost, 0);
  EXPECT_EQ(s.damaged[1].events_lost, 3);
  EXPECT_EQ(s.damaged[1].first_lost, 2);
  EXPECT_EQ(s.events_lost(), 3);
}

TEST(LcmLogScan, AGapThatOverflowsInt64IsUnknown) {
  const LogScan s = scan_lcm_log(write_log({-9151314442816817820, 72057594037957988}, "overflow.lcm"));
  EXPECT_EQ(s.events, 2u);
  ASSERT_EQ(s.damaged.size(), 1u);
  EXPECT_EQ(s.damaged[0].events_lost, -1);
  EXPECT_EQ(s.events_lost(), 0);
}

TEST(LcmLogScan, TheTotalOfHugeGapsSaturates) {
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  const LogScan s = scan_lcm_log(write_log({-(std::int64_t{1} << 62), std::int64_t{1} << 61, kMax}, "sum.lcm"));
  ASSERT_EQ(s.damaged.size(), 2u);
  EXPECT_GT(s.damaged[0].events_lost, 0);
  EXPECT_GT(s.damaged[1].events_lost, 0);
  EXPECT_EQ(s.events_lost(), kMax);
}

}  // namespace
}  // namespace vid::live
