/// @file test_vid_info.cpp
/// @brief The vid_info program: summary of valid folders (text and --json), and one error
/// line with exit code 1 on a broken folder.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "dataset_fixture.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

RunResult run_vid_info(const std::string& args) {
  ScratchDir dir("_stderr");
  const std::string err_file = (dir.path() / "stderr.txt").string();
  const std::string cmd = std::string(VID_BINARY_DIR) + "/bin/vid_info " + args + " 2>" + err_file;
  RunResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf;
  for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0;) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = read_text(err_file);
  return r;
}

TEST(VidInfo, SummarisesEurocSample) {
  const RunResult r = run_vid_info(std::string(VID_TEST_DATA_DIR) + "/euroc_sample");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("imu0 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cam0 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("state_groundtruth_estimate0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("752x480 radial-tangential"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("200.000"), std::string::npos) << "IMU rate missing:\n" << r.out;
}

TEST(VidInfo, JsonHasCountsRatesAndGaps) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kStereo);
  const RunResult r = run_vid_info(dir.path().string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::map<std::string, nlohmann::json> streams;
  for (const auto& s : j["streams"]) streams[s["name"]] = s;
  ASSERT_EQ(streams.count("imu0"), 1u);
  EXPECT_EQ(streams["imu0"]["count"], 98);
  EXPECT_NEAR(streams["imu0"]["largest_gap_s"].get<double>(), 0.015, 1e-12);
  EXPECT_EQ(streams["imu0"]["largest_gap_at_ns"].get<std::int64_t>(), 1403636579758555392 + 39 * 5'000'000LL);
  EXPECT_NEAR(streams["imu0"]["rate_hz"].get<double>(), 97.0 / 0.495, 1e-6);
  EXPECT_EQ(streams["cam1"]["count"], 11);
  EXPECT_EQ(streams["rotor0"]["count"], 50);
  EXPECT_EQ(streams["mass0"]["count"], 10);
  EXPECT_EQ(j["calibration"]["cameras"].size(), 2u);
  EXPECT_EQ(j["calibration"]["rotor"]["count"], 4);
  EXPECT_EQ(j["calibration"]["vehicle"]["mass_kg"], 3.1015);
}

TEST(VidInfo, ReportsDroppedRowsUnderOptions) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kMono);
  auto lines = read_lines(dir.path() / "mav0/imu0/data.csv");
  lines.insert(lines.begin() + 5, lines[5]);
  write_lines(dir.path() / "mav0/imu0/data.csv", lines);
  const RunResult fail = run_vid_info(dir.path().string());
  EXPECT_EQ(fail.exit_code, 1);
  const RunResult ok = run_vid_info(dir.path().string() + " --drop-bad-timestamps --json");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const auto j = nlohmann::json::parse(ok.out);
  EXPECT_EQ(j["streams"][0]["name"], "imu0");
  EXPECT_EQ(j["streams"][0]["dropped_bad_timestamps"], 1);
}

TEST(VidInfo, BrokenFolderGivesOneLineAndExitOne) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kMono);
  auto lines = read_lines(dir.path() / "mav0/imu0/data.csv");
  lines[6] = "123,abc";
  write_lines(dir.path() / "mav0/imu0/data.csv", lines);
  const RunResult r = run_vid_info(dir.path().string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.out.empty()) << r.out;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("vid_info: error: " + (dir.path() / "mav0/imu0/data.csv").string() + ":7:", 0), 0u) << r.err;

  const RunResult missing = run_vid_info("/nonexistent/folder");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(missing.err, "vid_info: error: /nonexistent/folder: no such dataset folder\n");
}

}  // namespace
}  // namespace vid::io::test
