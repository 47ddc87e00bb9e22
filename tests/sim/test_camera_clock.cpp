/// @file test_camera_clock.cpp
/// @brief The simulated camera-IMU time offset (cameras.time_offset_s, time_offset_jitter_s):
/// every camera stamp is the IMU-clock time of its image minus the offset, the true offset of
/// each frame is reported, and without the keys nothing changes.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "sim/scenario.h"
#include "sim/simulator.h"
#include "sim_test_util.h"

namespace vid::sim::test {
namespace {

struct CameraClock : SimSink {
  std::vector<TimeNs> stamps;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<std::pair<TimeNs, double>> offsets;
  std::vector<GroundTruthSample> gt;
  void on_camera(TimeNs t, std::uint64_t, const Eigen::Isometry3d& T_WI) override {
    stamps.push_back(t);
    poses.push_back(T_WI);
  }
  void on_time_offset(TimeNs t, double offset_s) override { offsets.emplace_back(t, offset_s); }
  void on_groundtruth(const GroundTruthSample& g) override { gt.push_back(g); }
};

CameraClock run(const std::string& camera_keys) {
  std::ifstream in(preset_path("hover"));
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto at = text.find("cameras:\n");
  EXPECT_NE(at, std::string::npos);
  text.insert(at + 9, camera_keys);
  Scenario sc = load_scenario_string(text, "hover+clock.yaml");
  sc.duration_s = 2.0;
  Simulator sim(sc);
  CameraClock rec;
  sim.run(rec);
  return rec;
}

TEST(CameraClock, StampIsTheImageTimeMinusTheOffset) {
  const CameraClock clean = run("");
  const CameraClock shifted = run("  time_offset_s: 0.010\n  time_offset_jitter_s: 0.0005\n");
  EXPECT_TRUE(clean.offsets.empty());
  ASSERT_EQ(shifted.stamps.size(), clean.stamps.size());
  ASSERT_EQ(shifted.offsets.size(), shifted.stamps.size());
  double sum = 0.0, sq = 0.0;
  for (std::size_t k = 0; k < shifted.stamps.size(); ++k) {
    SCOPED_TRACE(k);
    const auto [stamp, offset] = shifted.offsets[k];
    EXPECT_EQ(stamp, shifted.stamps[k]);
    // The image itself is unchanged (same pose, same IMU-clock time): only its stamp moves.
    EXPECT_TRUE(shifted.poses[k].isApprox(clean.poses[k], 1e-12));
    EXPECT_EQ(stamp + static_cast<TimeNs>(std::llround(offset * 1e9)), clean.stamps[k]);
    EXPECT_LE(std::abs(offset - 0.010), 3 * 0.0005 + 1e-12);
    if (k > 0) {
      EXPECT_GT(stamp, shifted.stamps[k - 1]);
    }
    sum += offset - 0.010;
    sq += (offset - 0.010) * (offset - 0.010);
  }
  const double n = static_cast<double>(shifted.stamps.size());  // 61 frames
  EXPECT_LT(std::abs(sum / n), 4 * 0.0005 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sq / n), 0.0005, 0.00015);
  // The image time is a ground-truth time every 0.1 s: the rendered pose is the one there.
  int matched = 0;
  for (std::size_t k = 0; k < clean.stamps.size(); ++k) {
    for (const GroundTruthSample& g : shifted.gt) {
      if (g.t_ns != clean.stamps[k]) continue;
      EXPECT_LT((shifted.poses[k].translation() - g.T_WI.p).norm(), 1e-12);
      ++matched;
    }
  }
  EXPECT_GE(matched, 20);
}

TEST(CameraClock, BadValuesNameTheKey) {
  try {
    load_scenario_string("cameras:\n  time_offset_jitter_s: 0.01\n", "j.yaml");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("time_offset_jitter_s"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vid::sim::test
