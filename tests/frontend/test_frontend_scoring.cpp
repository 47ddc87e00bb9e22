// Acceptance scoring of the KLT frontend on rendered simulator sequences (issue 5):
// vid17_like (30 s, stereo) and fast_yaw (3 rad/s, gyro prediction on/off).
// Sequences are rendered once by vid_sim into the build tree and reused while vid_sim and the
// preset are unchanged.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "track_scoring.h"

namespace fs = std::filesystem;

namespace vid {
namespace {

const fs::path kSim = fs::path(VID_BINARY_DIR) / "bin" / "vid_sim";
const fs::path kPresets = fs::path(VID_SOURCE_DIR) / "config" / "sim";

/// Render `preset` for `duration` s (cached); returns the dataset folder.
fs::path rendered(const std::string& preset, int duration) {
  const fs::path scenario = kPresets / preset;
  EXPECT_TRUE(fs::exists(kSim)) << "build vid_sim first: " << kSim;
  EXPECT_TRUE(fs::exists(scenario)) << scenario;
  const fs::path out = fs::path(VID_BINARY_DIR) / "tests" / "frontend" / "rendered" /
                       (scenario.stem().string() + "_" + std::to_string(duration) + "s");
  const fs::path marker = out / "rendered.ok";
  const bool fresh = fs::exists(marker) && fs::last_write_time(marker) > fs::last_write_time(kSim) &&
                     fs::last_write_time(marker) > fs::last_write_time(scenario);
  if (!fresh) {
    fs::remove_all(out);
    fs::create_directories(out.parent_path());
    const std::string cmd = kSim.string() + " --scenario " + scenario.string() + " --out " +
                            out.string() + " --duration " + std::to_string(duration) +
                            " > " + out.string() + ".log 2>&1";
    const int rc = std::system(cmd.c_str());
    EXPECT_EQ(rc, 0) << cmd;
    std::ofstream(marker) << "ok\n";
  }
  return out;
}

TEST(FrontendScoring, Vid17LikeStereo30s) {
  const fs::path ds = rendered("vid17_like_short.yaml", 30);
  const sim::Scene scene = sim::scene_from_scenario_file((kPresets / "vid17_like_short.yaml").string());
  FrontendParams p;  // defaults: 150 features requested
  const test::TrackScore s = test::score_sequence(ds, p, scene, true);
  test::print_score("vid17_like 30s stereo", s);
  EXPECT_GE(s.frames, 850u);
  EXPECT_LE(s.median_err_px, 0.3);
  EXPECT_LE(s.drift_fraction, 0.01);
  EXPECT_GE(s.mean_track_length, 10.0);
  EXPECT_GE(s.mean_features, 120.0);
  EXPECT_LE(s.median_disp_err_px, 0.3);
  EXPECT_GE(s.stereo_fraction, 0.5);
}

TEST(FrontendScoring, FastYawGyroPrediction) {
  // fast_yaw: hover, yaw rate ramps to 3 rad/s (1 s delay + 2 s ramp); 7 s gives 4 s at full
  // rate. Survival is counted on frames rotating at >= 2.9 rad/s only.
  const fs::path ds = rendered("fast_yaw.yaml", 7);
  const sim::Scene scene = sim::scene_from_scenario_file((kPresets / "fast_yaw.yaml").string());
  FrontendParams with;
  FrontendParams without;
  without.gyro_prediction = false;
  const test::TrackScore a = test::score_sequence(ds, with, scene, false, 2.9);
  const test::TrackScore b = test::score_sequence(ds, without, scene, false, 2.9);
  test::print_score("fast_yaw with gyro", a);
  test::print_score("fast_yaw without gyro", b);
  EXPECT_GE(a.kept_fraction, 0.6);
  EXPECT_GE(a.kept_fraction, b.kept_fraction);
  EXPECT_LE(a.drift_fraction, 0.01);
  EXPECT_LE(a.median_err_px, 0.3);
}

}  // namespace
}  // namespace vid
