// vid_track end to end on small synthetic dataset folders (docs/formats.md §1): a single stereo pair,
// a short stereo sequence, and bad input (one-line errors, non-zero exit).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>
#include <string>

#include "synthetic_images.h"

namespace fs = std::filesystem;

namespace vid {
namespace {

const std::string kTrack = std::string(VID_BINARY_DIR) + "/bin/vid_track";

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

std::string cam_yaml(double tx) {
  std::ostringstream s;
  s << "sensor_type: camera\ncomment: synthetic\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1.0, 0.0, 0.0, "
    << tx << ", 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]\n"
    << "rate_hz: 20\nresolution: [640, 480]\ncamera_model: pinhole\n"
    << "intrinsics: [400.0, 400.0, 319.5, 239.5]\ndistortion_model: radial-tangential\n"
    << "distortion_coefficients: [0.0, 0.0, 0.0, 0.0]\n";
  return s.str();
}

/// Stereo folder with `frames` frames: a plane at 2 m (20 px disparity), moving 2 px per frame.
fs::path make_dataset(const std::string& name, int frames) {
  const fs::path root = fs::path(::testing::TempDir()) / ("vid_track_" + name);
  fs::remove_all(root);
  const fs::path mav0 = root / "mav0";
  std::string imu = "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
                    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  for (int i = 0; i <= frames * 10; ++i) {
    imu += std::to_string(1'000'000'000LL + i * 5'000'000LL) + ",0,0,0,0,0,9.81\n";
  }
  write(mav0 / "imu0" / "data.csv", imu);
  write(mav0 / "imu0" / "sensor.yaml",
        "sensor_type: imu\nrate_hz: 200\ngyroscope_noise_density: 1.0e-4\n"
        "gyroscope_random_walk: 1.0e-5\naccelerometer_noise_density: 2.0e-3\n"
        "accelerometer_random_walk: 3.0e-3\n");
  write(mav0 / "cam0" / "sensor.yaml", cam_yaml(0.0));
  write(mav0 / "cam1" / "sensor.yaml", cam_yaml(0.1));
  const cv::Mat base = test::textured_image(640, 480, 3);
  std::string csv = "#timestamp [ns],filename\n";
  fs::create_directories(mav0 / "cam0" / "data");
  fs::create_directories(mav0 / "cam1" / "data");
  for (int k = 0; k < frames; ++k) {
    const long long t = 1'000'000'000LL + k * 50'000'000LL;
    const cv::Mat l = test::warp(base, cv::Matx33d(1, 0, 2.0 * k, 0, 1, 0, 0, 0, 1));
    const cv::Mat r = test::warp(base, cv::Matx33d(1, 0, 2.0 * k - 20.0, 0, 1, 0, 0, 0, 1));
    cv::imwrite((mav0 / "cam0" / "data" / (std::to_string(t) + ".png")).string(), l);
    cv::imwrite((mav0 / "cam1" / "data" / (std::to_string(t) + ".png")).string(), r);
    csv += std::to_string(t) + "," + std::to_string(t) + ".png\n";
  }
  write(mav0 / "cam0" / "data.csv", csv);
  write(mav0 / "cam1" / "data.csv", csv);
  return root;
}

int run(const std::string& args, std::string* err = nullptr) {
  // One file per test: CTest runs the tests of this binary as parallel processes.
  const std::string err_file = ::testing::TempDir() + "/vid_track_stderr_" +
                               ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                               ".txt";
  const int rc = std::system((kTrack + " " + args + " 2> " + err_file).c_str());
  if (err) {
    std::ifstream f(err_file);
    *err = std::string(std::istreambuf_iterator<char>(f), {});
  }
  return rc;
}

struct Row {
  long long t;
  int cam;
  unsigned long long id;
  double u, v;
};

std::vector<Row> read_tracks(const fs::path& p) {
  std::ifstream f(p);
  std::string line;
  std::getline(f, line);
  EXPECT_EQ(line, "#timestamp [ns],cam_id,feature_id,u [px],v [px]");
  std::vector<Row> rows;
  while (std::getline(f, line)) {
    Row r{};
    EXPECT_EQ(std::sscanf(line.c_str(), "%lld,%d,%llu,%lf,%lf", &r.t, &r.cam, &r.id, &r.u, &r.v), 5);
    rows.push_back(r);
  }
  return rows;
}

TEST(VidTrack, SingleStereoPairWithDrawing) {
  ASSERT_TRUE(fs::exists(kTrack)) << "build vid_track first";
  const fs::path ds = make_dataset("pair", 1);
  const fs::path out = ds / "tracks.csv", draw = ds / "draw";
  ASSERT_EQ(run("--dataset " + ds.string() + " --out " + out.string() + " --draw " + draw.string()), 0);
  const auto rows = read_tracks(out);
  std::map<unsigned long long, Row> left, right;
  for (const auto& r : rows) (r.cam == 0 ? left : right)[r.id] = r;
  EXPECT_GE(left.size(), 140u);
  EXPECT_GE(right.size(), left.size() * 85 / 100);
  for (const auto& [id, r] : right) {
    ASSERT_TRUE(left.count(id));
    EXPECT_NEAR(left[id].u - r.u, 20.0, 0.3);
    EXPECT_NEAR(left[id].v - r.v, 0.0, 0.3);
  }
  ASSERT_TRUE(fs::exists(draw / "1000000000.png"));
  const cv::Mat img = cv::imread((draw / "1000000000.png").string());
  EXPECT_EQ(img.cols, 1280);
  EXPECT_EQ(img.rows, 480);
}

TEST(VidTrack, SequenceKeepsIdsAndUsesConfig) {
  const fs::path ds = make_dataset("seq", 6);
  const fs::path cfg = ds / "frontend.yaml", out = ds / "tracks.csv";
  write(cfg, "num_features: 100\nequalization: clahe\n");
  ASSERT_EQ(run("--dataset " + ds.string() + " --config " + cfg.string() + " --out " + out.string()), 0);
  std::map<unsigned long long, std::vector<Row>> by_id;
  std::map<long long, int> per_frame;
  for (const auto& r : read_tracks(out)) {
    if (r.cam != 0) continue;
    by_id[r.id].push_back(r);
    ++per_frame[r.t];
  }
  ASSERT_EQ(per_frame.size(), 6u);
  for (const auto& [t, n] : per_frame) EXPECT_LE(n, 100);
  int full = 0;
  for (const auto& [id, v] : by_id) {
    if (v.size() == 6) {
      ++full;
      EXPECT_NEAR(v.back().u - v.front().u, 10.0, 0.3);
    }
  }
  EXPECT_GE(full, 80);
}

TEST(VidTrack, BadInputGivesOneLineError) {
  std::string err;
  EXPECT_NE(run("--dataset /nonexistent/folder --out /tmp/x.csv", &err), 0);
  EXPECT_NE(err.find("vid_track: error:"), std::string::npos) << err;
  EXPECT_NE(err.find("/nonexistent/folder"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;

  const fs::path ds = make_dataset("badcfg", 1);
  const fs::path cfg = ds / "frontend.yaml";
  write(cfg, "num_featurs: 100\n");
  EXPECT_NE(run("--dataset " + ds.string() + " --config " + cfg.string() + " --out " +
                    (ds / "t.csv").string(), &err), 0);
  EXPECT_NE(err.find("frontend.yaml"), std::string::npos) << err;
  EXPECT_NE(err.find("num_featurs"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

}  // namespace
}  // namespace vid
