/// @file test_stream_gaps.cpp
/// @brief A sensor-stream gap beyond ReaderOptions::max_gap_periods is a load-time error naming
/// file, line and gap (issue #28), a counted warning under gaps_as_warnings; reference streams
/// (ground truth) may pause.

#include <gtest/gtest.h>

#include "dataset_fixture.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

namespace fs = std::filesystem;

class StreamGap : public ::testing::Test {
 protected:
  void SetUp() override {
    write_sequence(dir_.path(), SeqKind::kFeatures);
    mav0_ = dir_.path() / "mav0";
  }
  /// Shift every data row of @p rel from data row @p from on by @p shift_ns; returns the file
  /// line of the first shifted row.
  std::size_t shift_rows(const std::string& rel, std::size_t from, TimeNs shift_ns) {
    auto lines = read_lines(mav0_ / rel);
    std::size_t row = 0, first_line = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (lines[i].empty() || lines[i][0] == '#') continue;
      if (row++ < from) continue;
      const auto comma = lines[i].find(',');
      lines[i] = std::to_string(std::stoll(lines[i].substr(0, comma)) + shift_ns) + lines[i].substr(comma);
      if (first_line == 0) first_line = i + 1;
    }
    write_lines(mav0_ / rel, lines);
    return first_line;
  }
  ScratchDir dir_;
  fs::path mav0_;
};

TEST_F(StreamGap, ImuGapIsAnErrorNamingFileLineAndGap) {
  const std::size_t line = shift_rows("imu0/data.csv", 60, 3'600'000'000'000);  // one hour
  const std::string msg = read_error(dir_.path());
  EXPECT_NE(msg.find((mav0_ / "imu0/data.csv").string() + ": line " + std::to_string(line) +
                     ": time gap of 3600.005 s after the previous row, more than 100 sample periods of 5.000 ms"),
            std::string::npos)
      << msg;
}

TEST_F(StreamGap, BoundIsConfigurableAndCanBeOff) {
  shift_rows("imu0/data.csv", 60, 400'000'000);  // 0.4 s = 81 periods: within the default bound
  EXPECT_EQ(read_error(dir_.path()), "");
  ReaderOptions tight;
  tight.max_gap_periods = 50;
  EXPECT_NE(read_error(dir_.path(), tight).find("more than 50 sample periods"), std::string::npos);
  ReaderOptions off;
  off.max_gap_periods = 0;
  shift_rows("imu0/data.csv", 80, 3'600'000'000'000);
  EXPECT_EQ(read_error(dir_.path(), off), "");
}

TEST_F(StreamGap, WarningsOptionCountsAndReports) {
  shift_rows("imu0/data.csv", 60, 10'000'000'000);
  std::vector<std::string> warnings;
  ReaderOptions o;
  o.gaps_as_warnings = true;
  o.warn = [&](const std::string& w) { warnings.push_back(w); };
  DatasetReader reader(dir_.path(), o);
  while (reader.next()) {
  }
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("imu0/data.csv: line "), std::string::npos) << warnings[0];
  for (const auto& s : reader.stats())
    EXPECT_EQ(s.gaps_over_bound, s.name == "imu0" ? 1u : 0u) << s.name;
}

TEST_F(StreamGap, GapInAnEarlyRowIsFoundOnceThePeriodIsKnown) {
  const std::size_t line = shift_rows("imu0/data.csv", 3, 3'000'000'000);
  EXPECT_NE(read_error(dir_.path()).find("imu0/data.csv: line " + std::to_string(line) + ": time gap"),
            std::string::npos);
}

TEST_F(StreamGap, GroundTruthMayPause) {
  shift_rows("state_groundtruth_estimate0/data.csv", 50, 3'600'000'000'000);
  EXPECT_EQ(read_error(dir_.path()), "");
}

}  // namespace
}  // namespace vid::io::test
