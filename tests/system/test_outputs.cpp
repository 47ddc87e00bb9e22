/// Output files of a run: formats of docs/formats.md §2 and flushing after every row (an interrupted
/// run keeps what it wrote).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "vid_system/outputs.h"

namespace vid::system {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream f(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(f, l);) out.push_back(l);
  return out;
}

int fields(const std::string& line, char sep) {
  int n = 1;
  for (char c : line) n += c == sep ? 1 : 0;
  return n;
}

TEST(RunOutputs, RowsAreOnDiskBeforeClose) {
  const fs::path dir = fs::temp_directory_path() / "vid_run_test_outputs";
  fs::remove_all(dir);
  fs::create_directories(dir);
  RunOutputs out(dir, /*write_force=*/true);
  EstimateRow r;
  r.t_ns = 1700000000123456789LL;
  r.T_WI.p = {1.0, 2.0, 3.0};
  r.T_WI.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  r.F_ext_I = {0.1, 0.2, 0.3};
  r.sigma.setConstant(0.01);
  out.write_estimate(r);
  TimingRow t;
  t.t_ns = r.t_ns;
  t.total_ms = 1.5;
  out.write_timing(t);

  // Not closed yet: a reader (or a crash) must already see the rows.
  const auto tum = lines_of(dir / "trajectory_tum.txt");
  ASSERT_EQ(tum.size(), 2u);
  EXPECT_EQ(tum[0][0], '#');
  EXPECT_EQ(tum[1].rfind("1700000000.123456789 1.000000000 2.000000000 3.000000000 ", 0), 0u) << tum[1];
  EXPECT_EQ(fields(tum[1], ' '), 8);
  std::istringstream is(tum[1]);
  double ts, x, y, z, qx, qy, qz, qw;
  is >> ts >> x >> y >> z >> qx >> qy >> qz >> qw;
  EXPECT_NEAR(qz, std::sin(0.15), 1e-9);  // TUM order qx qy qz qw
  EXPECT_NEAR(qw, std::cos(0.15), 1e-9);

  const auto state = lines_of(dir / "state.csv");
  ASSERT_EQ(state.size(), 2u);
  EXPECT_EQ(fields(state[0], ','), 1 + 3 + 4 + 3 + 3 + 3 + 3 + 18);
  EXPECT_EQ(fields(state[1], ','), fields(state[0], ','));
  const auto force = lines_of(dir / "force.csv");
  ASSERT_EQ(force.size(), 2u);
  EXPECT_EQ(fields(force[1], ','), 10);
  EXPECT_EQ(lines_of(dir / "timing.csv").size(), 2u);
  out.close();
  fs::remove_all(dir);
}

TEST(RunOutputs, ImuModeForceFileHasOnlyHeader) {
  const fs::path dir = fs::temp_directory_path() / "vid_run_test_outputs_imu";
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    RunOutputs out(dir, /*write_force=*/false);
    out.write_estimate(EstimateRow{});
    out.close();
  }
  EXPECT_EQ(lines_of(dir / "force.csv").size(), 1u);
  EXPECT_EQ(lines_of(dir / "trajectory_tum.txt").size(), 2u);
  fs::remove_all(dir);
}

TEST(RunOutputs, UnwritableFolderNamesTheFile) {
  try {
    RunOutputs out("/nonexistent_dir_for_vid_run_test", true);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory_tum.txt"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vid::system
