/// @file test_camera_along.cpp
/// @brief vid_sim --camera-along: the recorded-trajectory interpolation (PoseTrack), strict TUM
/// reading, feature observations that reproject exactly at the interpolated poses, and a
/// dataset folder whose other streams stay untouched.

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "frontend/camera_model.h"
#include "geometry/so3.h"
#include "io/csv_reader.h"
#include "io/errors.h"
#include "sim/camera_along.h"
#include "sim/pose_track.h"
#include "sim/scenario.h"

namespace vid::sim {
namespace {

namespace fs = std::filesystem;

/// A fresh folder under the system temp folder, removed with its contents at scope exit.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("camalong_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string preset(const std::string& n) { return std::string(VID_SOURCE_DIR) + "/config/sim/" + n + ".yaml"; }

/// A flight sampled like motion capture: circle (radius 2 m, 1.2 rad/s) following its tangent
/// with a roll/pitch wobble, or a straight line at 2 m/s with a constant yaw rate.
struct Path {
  bool circle = true;
  Eigen::Vector3d p(double t) const {
    if (!circle) return {-3.0 + 2.0 * t, 0.5, 1.2 + 0.1 * t};
    return {2.0 * std::cos(1.2 * t), 2.0 * std::sin(1.2 * t), 1.5 + 0.2 * std::sin(2.0 * t)};
  }
  Eigen::Quaterniond q(double t) const {
    if (!circle) return Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * t - 0.2, Eigen::Vector3d::UnitZ()));
    return Eigen::Quaterniond(Eigen::AngleAxisd(1.2 * t + M_PI / 2, Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(0.3 * std::sin(3.0 * t), Eigen::Vector3d::UnitX()) *
                              Eigen::AngleAxisd(0.2 * std::cos(2.5 * t), Eigen::Vector3d::UnitY()));
  }
};

constexpr TimeNs kT0 = 1'525'745'865'001'655'340LL;

/// TUM file of @p path sampled at 100 Hz for @p duration_s (9 decimals, as vid_run writes).
fs::path write_tum(const fs::path& dir, const Path& path, double duration_s, const std::string& name = "traj.tum") {
  const fs::path f = dir / name;
  std::FILE* out = std::fopen(f.c_str(), "w");
  std::fprintf(out, "# t x y z qx qy qz qw\n");
  for (int k = 0; k * 0.01 <= duration_s + 1e-9; ++k) {
    const TimeNs t = kT0 + k * 10'000'000LL;
    const Eigen::Vector3d p = path.p(k * 0.01);
    const Eigen::Quaterniond q = path.q(k * 0.01);
    std::fprintf(out, "%lld.%09lld %.12f %.12f %.12f %.12f %.12f %.12f %.12f\n", static_cast<long long>(t / 1'000'000'000),
                 static_cast<long long>(t % 1'000'000'000), p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
  }
  std::fclose(out);
  return f;
}

std::string read_file(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::map<std::string, std::string> read_tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), root).string()] = read_file(e.path());
  }
  return files;
}

Scenario features_scenario() {
  Scenario sc = load_scenario(preset("recorded_room"));
  sc.noise = false;
  sc.cameras.images = false;
  sc.cameras.features = true;
  return sc;
}

TEST(PoseTrack, ReproducesAStraightLineAndAConstantRateExactly) {
  const Path line{false};
  std::vector<TimeNs> t;
  std::vector<Eigen::Vector3d> p;
  std::vector<Eigen::Quaterniond> q;
  for (int k = 0; k <= 50; ++k) {
    t.push_back(kT0 + k * 10'000'000LL + (k % 3) * 1'000'000LL);  // uneven spacing
    const double s = static_cast<double>(t.back() - kT0) * 1e-9;
    p.push_back(line.p(s));
    q.push_back(line.q(s));
  }
  const PoseTrack track(t, p, q);
  for (TimeNs tt = kT0; tt <= track.end_ns(); tt += 3'333'333) {
    const double s = static_cast<double>(tt - kT0) * 1e-9;
    const Eigen::Isometry3d T = track.pose(tt);
    EXPECT_LT((T.translation() - line.p(s)).norm(), 1e-12);
    EXPECT_LT(so3::log(T.linear().transpose() * line.q(s).toRotationMatrix()).norm(), 1e-12);
    const BodyMotion m = track.motion(tt);
    EXPECT_LT((m.v_WI - Eigen::Vector3d(2.0, 0.0, 0.1)).norm(), 1e-9);
    EXPECT_LT(m.a_WI.norm(), 1e-7);
    EXPECT_LT((m.w_I - Eigen::Vector3d(0.0, 0.0, 0.3)).norm(), 1e-9);
  }
}

TEST(PoseTrack, CircleInterpolationMatchesThePathAndItsDerivatives) {
  const TempDir tmp("circle");
  const fs::path& dir = tmp.path;
  const Path circle;
  const PoseTrack track = PoseTrack::read_tum(write_tum(dir, circle, 3.0));
  ASSERT_EQ(track.size(), 301u);
  EXPECT_EQ(track.start_ns(), kT0);  // decimal stamp text converted exactly
  EXPECT_EQ(track.end_ns(), kT0 + 3'000'000'000LL);
  double worst_p = 0.0, worst_v = 0.0;
  for (TimeNs tt = kT0 + 100'000'000; tt < kT0 + 2'900'000'000LL; tt += 3'333'333) {
    const double s = static_cast<double>(tt - kT0) * 1e-9;
    const Eigen::Isometry3d T = track.pose(tt);
    worst_p = std::max(worst_p, (T.translation() - circle.p(s)).norm());
    // Slerp between 10 ms samples: within a hundredth of a degree of the smooth rotation.
    EXPECT_LT(so3::log(T.linear().transpose() * circle.q(s).toRotationMatrix()).norm(), 2e-4);
    // The motion is the derivative of the interpolated pose (central differences, 0.1 ms).
    const TimeNs d = 100'000;
    const BodyMotion m = track.motion(tt);
    const Eigen::Vector3d v_num = (track.pose(tt + d).translation() - track.pose(tt - d).translation()) / 2e-4;
    EXPECT_LT((m.v_WI - v_num).norm(), 1e-5);
    const Eigen::Vector3d a_num = (track.motion(tt + d).v_WI - track.motion(tt - d).v_WI) / 2e-4;
    EXPECT_LT((m.a_WI - a_num).norm(), 1e-3);
    const Eigen::Vector3d v_true = (circle.p(s + 1e-6) - circle.p(s - 1e-6)) / 2e-6;
    worst_v = std::max(worst_v, (m.v_WI - v_true).norm());
    EXPECT_LT((m.a_WI - (circle.p(s + 1e-4) - 2.0 * circle.p(s) + circle.p(s - 1e-4)) / 1e-8).norm(), 0.05);
    // Body rate: the slerp's, i.e. Log(R(t)^T R(t + d)) / d inside an interval.
    if ((tt - kT0) % 10'000'000 > d && (tt - kT0) % 10'000'000 < 10'000'000 - d) {
      const Eigen::Vector3d w_num = so3::log(T.linear().transpose() * track.pose(tt + d).linear()) / 1e-4;
      EXPECT_LT((m.w_I - w_num).norm(), 1e-6);
    }
  }
  EXPECT_LT(worst_p, 1e-6);  // cubic: O(h^4) for a smooth path
  EXPECT_LT(worst_v, 1e-4);
  // At the samples the track is the recording.
  EXPECT_LT((track.pose(kT0 + 1'230'000'000LL).translation() - circle.p(1.23)).norm(), 1e-11);
}

TEST(PoseTrack, BadTumFilesFailWithFileAndLine) {
  const TempDir tmp("bad");
  const fs::path& dir = tmp.path;
  const auto expect_error = [&](const std::string& text, const std::string& where, const std::string& what) {
    const fs::path f = dir / "bad.tum";
    std::ofstream(f) << text;
    try {
      PoseTrack::read_tum(f);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const io::DatasetError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(f.string() + ":" + where, 0), 0u) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  };
  const std::string ok1 = "10.00 0 0 1 0 0 0 1\n", ok2 = "10.01 0 0 1 0 0 0 1\n";
  expect_error(ok1 + ok2 + "10.01 0 0 1 0 0 0 1\n", "3:", "not after the previous row");
  expect_error("# header\n" + ok1 + "9.5 0 0 1 0 0 0 1\n", "3:", "not after the previous row");
  expect_error(ok1 + "10.01 0 0 1 0 0 0.5 1\n", "2:", "not a unit quaternion");
  expect_error(ok1 + "10.01 0 0 1 0 0 1\n", "2:", "expected 8 columns, got 7");
  expect_error(ok1 + ok2 + "10.02 0 0 1 0 0 0 1 5\n", "3:", "expected 8 columns, got 9");
  expect_error(ok1 + "10.01 0 zero 1 0 0 0 1\n", "2:", "column 3 'y'");
  expect_error(ok1 + "10.01 0 0 nan 0 0 0 1\n", "2:", "column 4 'z'");
  expect_error("-1.0 0 0 1 0 0 0 1\n" + ok1, "1:", "negative timestamp");
  expect_error(ok1, "", "need at least 2 poses");
  // Other number forms are accepted: exponents and a '+' sign.
  std::ofstream(dir / "exp.tum") << "1.0e1 0 0 1 0 0 0 1\n+10.5 0 0 1 0 0 0 1\n";
  const PoseTrack t = PoseTrack::read_tum(dir / "exp.tum");
  EXPECT_EQ(t.start_ns(), 10'000'000'000LL);
  EXPECT_EQ(t.end_ns(), 10'500'000'000LL);
}

/// Every written observation is the exact projection of its landmark at the interpolated pose.
void expect_exact_reprojection(const Path& path, const std::string& name) {
  const TempDir tmp(name);
  const fs::path& dir = tmp.path;
  const PoseTrack track = PoseTrack::read_tum(write_tum(dir, path, 2.0));
  const Scenario sc = features_scenario();
  const std::uint64_t frames = write_camera_along(sc, track, dir / "out", false);
  EXPECT_EQ(frames, 61u);  // 2 s at 30 Hz from the first pose, both ends included
  const std::vector<TimeNs> times = camera_times_along(track, 30.0);
  ASSERT_EQ(times.size(), 61u);
  EXPECT_EQ(times.front(), kT0);
  EXPECT_EQ(times[1], kT0 + 33'333'333);

  std::map<std::uint64_t, Eigen::Vector3d> landmarks;
  io::CsvReader lm(dir / "out/mav0/landmarks.csv");
  while (lm.next_row()) {
    landmarks[static_cast<std::uint64_t>(lm.get_int(0, "id"))] =
        Eigen::Vector3d(lm.get_double(1, "x"), lm.get_double(2, "y"), lm.get_double(3, "z"));
  }
  ASSERT_GT(landmarks.size(), 100u);
  std::vector<std::unique_ptr<CameraModel>> cams;
  for (const CameraCalib& c : sc.cameras.cameras) cams.push_back(CameraModel::create(c));
  io::CsvReader feat(dir / "out/mav0/feat0/data.csv");
  std::map<TimeNs, int> per_frame;
  double worst = 0.0;
  while (feat.next_row()) {
    const TimeNs t = feat.get_int(0, "timestamp");
    const int cam = static_cast<int>(feat.get_int(1, "cam_id"));
    const Eigen::Vector2d uv(feat.get_double(3, "u"), feat.get_double(4, "v"));
    ASSERT_TRUE(std::binary_search(times.begin(), times.end(), t)) << t;
    ASSERT_TRUE(landmarks.count(static_cast<std::uint64_t>(feat.get_int(2, "feature_id"))));
    const Eigen::Vector3d p_W = landmarks.at(static_cast<std::uint64_t>(feat.get_int(2, "feature_id")));
    const Eigen::Isometry3d T_WC = track.pose(t) * sc.cameras.cameras.at(cam).T_IC;
    Eigen::Vector2d uv_ref;
    ASSERT_TRUE(cams.at(cam)->project(T_WC.inverse() * p_W, &uv_ref));
    worst = std::max(worst, (uv - uv_ref).norm());
    ++per_frame[t];
  }
  EXPECT_LT(worst, 1e-6) << "px";
  EXPECT_EQ(per_frame.size(), times.size()) << "every frame sees features";
  for (const auto& [t, n] : per_frame) EXPECT_GE(n, 100) << t;  // stereo, 150 per camera targeted
}

TEST(CameraAlong, FeaturesReprojectExactlyAlongAStraightLine) { expect_exact_reprojection(Path{false}, "line"); }
TEST(CameraAlong, FeaturesReprojectExactlyAlongACircle) { expect_exact_reprojection(Path{true}, "circ"); }

TEST(CameraAlong, LeavesOtherStreamsUntouchedAndRefusesExistingCameraStreams) {
  const TempDir tmp("keep");
  const fs::path& dir = tmp.path;
  const PoseTrack track = PoseTrack::read_tum(write_tum(dir, Path{}, 1.0));
  const fs::path root = dir / "seq";
  fs::create_directories(root / "mav0/imu0");
  fs::create_directories(root / "mav0/state_groundtruth_estimate0");
  std::ofstream(root / "mav0/imu0/data.csv") << "#timestamp [ns],w\n1,2\n";
  std::ofstream(root / "mav0/state_groundtruth_estimate0/data.csv") << "#gt\n";
  std::ofstream(root / "mav0/vehicle.yaml") << "mass_kg: 0.915\n";
  std::ofstream(root / "notes.txt") << "mine\n";
  const auto before = read_tree(root);
  const Scenario sc = features_scenario();
  write_camera_along(sc, track, root, false);
  const auto after = read_tree(root);
  for (const auto& [name, content] : before) {
    ASSERT_TRUE(after.count(name)) << name;
    EXPECT_EQ(after.at(name), content) << name;
  }
  for (const auto& [name, content] : after) {
    if (before.count(name)) continue;
    const bool camera_stream = name.rfind("mav0/cam0/", 0) == 0 || name.rfind("mav0/cam1/", 0) == 0 ||
                               name.rfind("mav0/feat0/", 0) == 0 || name == "mav0/landmarks.csv";
    EXPECT_TRUE(camera_stream) << "wrote " << name;
  }
  EXPECT_TRUE(after.count("mav0/cam0/sensor.yaml") && after.count("mav0/cam1/sensor.yaml"));
  EXPECT_TRUE(after.count("mav0/feat0/data.csv") && after.count("mav0/landmarks.csv"));

  // A second run refuses, naming the streams, and changes nothing.
  try {
    write_camera_along(sc, track, root, false);
    ADD_FAILURE() << "existing camera streams overwritten without --overwrite";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mav0/cam0"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_tree(root), after);
  // --overwrite replaces exactly the camera streams (stale files go), deterministically.
  std::ofstream(root / "mav0/cam0/stale.png") << "x";
  write_camera_along(sc, track, root, true);
  EXPECT_EQ(read_tree(root), after);
}

int run_vid_sim(const std::string& args, std::string* err) {
  const fs::path err_file = fs::temp_directory_path() / ("camalong_err_" + std::to_string(::getpid()));
  const std::string cmd = std::string(VID_BINARY_DIR) + "/bin/vid_sim " + args + " > /dev/null 2> " + err_file.string();
  const int status = std::system(cmd.c_str());
  *err = read_file(err_file);
  fs::remove(err_file);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(CameraAlong, ProgramRendersImagesAndReportsErrorsInOneLine) {
  const TempDir tmp("cli");
  const fs::path& dir = tmp.path;
  const fs::path tum = write_tum(dir, Path{false}, 0.3);
  const std::string base = "--scenario " + preset("recorded_room") + " --quiet --out " + (dir / "seq").string();
  std::string err;
  ASSERT_EQ(run_vid_sim(base + " --camera-along " + tum.string(), &err), 0) << err;
  for (const char* cam : {"cam0", "cam1"}) {
    io::CsvReader csv(dir / "seq/mav0" / cam / "data.csv");
    int rows = 0;
    while (csv.next_row()) {
      ++rows;
      EXPECT_TRUE(fs::is_regular_file(dir / "seq/mav0" / cam / "data" / csv.field(1))) << csv.field(1);
    }
    EXPECT_EQ(rows, 10);  // 0.3 s at 30 Hz, both ends
  }
  EXPECT_TRUE(fs::is_regular_file(dir / "seq/mav0/feat0/data.csv"));
  EXPECT_FALSE(fs::exists(dir / "seq/mav0/imu0"));
  EXPECT_FALSE(fs::exists(dir / "seq/mav0/state_groundtruth_estimate0"));

  // Existing streams: refused (exit 1, one line), replaced with --overwrite.
  EXPECT_EQ(run_vid_sim(base + " --camera-along " + tum.string(), &err), 1);
  EXPECT_NE(err.find("already exist"), std::string::npos) << err;
  EXPECT_EQ(run_vid_sim(base + " --camera-along " + tum.string() + " --overwrite --features-only", &err), 0) << err;
  EXPECT_FALSE(fs::exists(dir / "seq/mav0/cam0/data.csv")) << "--overwrite leaves no stale images";

  // Bad trajectory: exit 1, one line naming file:line.
  std::ofstream(dir / "bad.tum") << "1.0 0 0 1 0 0 0 1\n1.1 0 0 1 0 0 0.3 1\n";
  EXPECT_EQ(run_vid_sim(base + "2 --camera-along " + (dir / "bad.tum").string(), &err), 1);
  EXPECT_NE(err.find((dir / "bad.tum").string() + ":2:"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  // Usage errors: exit 2.
  EXPECT_EQ(run_vid_sim(base + "3 --camera-along " + tum.string() + " --duration 3", &err), 2) << err;
  EXPECT_EQ(run_vid_sim(base + "3 --overwrite", &err), 2) << err;
}

}  // namespace
}  // namespace vid::sim
