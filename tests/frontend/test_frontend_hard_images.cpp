// The KLT frontend on the realistic-image presets of issue #23 (config/sim/README.md "Images"):
// vid18_hard (8 ms exposure with motion blur, auto-exposure, vignetting, shot + read noise,
// flicker, a lamp, plain floor / wall / boxes; its ground-truth world turned by 150 deg) and
// dark_room (12 % light: exposure at its 30 ms limit, gain up to 8x, more plain surfaces).
// Acceptance: >= 100 tracked features per frame (median), track error median <= 0.3 px.
// Also impacts (10 s: a 60 N wall bump at 4 s, a 3 g ground bump at 9.5 s), the jolts a
// tracker that predicts each feature from its last motion (direct_alignment) must survive: it
// must keep and place tracks as well as KLT on every point does.
#include <gtest/gtest.h>

#include <future>
#include <memory>
#include <string>

#include "rendered_sequence.h"
#include "track_scoring.h"

namespace vid {
namespace {

constexpr int kDurationS = 8;
constexpr int kImpactsS = 10;

/// Renders (in parallel) and scores both presets once for all tests of the binary.
class HardImages : public ::testing::Test {
 protected:
  struct Scores {
    std::string error;
    test::TrackScore vid18_hard, dark_room, impacts_direct, impacts_klt;
  };

  static test::TrackScore score(const std::string& preset, const test::Rendered& r) {
    const auto scene = sim::scene_from_scenario_file((test::kPresets / preset).string());
    return test::score_sequence(r.dir, FrontendParams{}, scene, true, 0.0,
                                test::scene_to_groundtruth(preset, kDurationS));
  }

  static void SetUpTestSuite() {
    scores_ = std::make_unique<Scores>();
    auto dark = std::async(std::launch::async, [] { return test::render("dark_room.yaml", kDurationS); });
    const test::Rendered v18 = test::render("vid18_hard.yaml", kDurationS);
    const test::Rendered im = test::render("impacts_short.yaml", kImpactsS);
    const test::Rendered dr = dark.get();
    if (!v18.error.empty() || !dr.error.empty() || !im.error.empty()) {
      scores_->error = v18.error + " " + dr.error + " " + im.error;
      return;
    }
    {
      const auto scene = sim::scene_from_scenario_file((test::kPresets / "impacts_short.yaml").string());
      const auto R_GS = test::scene_to_groundtruth("impacts_short.yaml", kImpactsS);
      FrontendParams klt;
      klt.direct_alignment = false;
      auto direct = std::async(std::launch::async, [&] {
        return test::score_sequence(im.dir, FrontendParams{}, scene, true, 0.0, R_GS);
      });
      scores_->impacts_klt = test::score_sequence(im.dir, klt, scene, true, 0.0, R_GS);
      scores_->impacts_direct = direct.get();
      test::print_score("impacts 10s stereo, direct alignment", scores_->impacts_direct);
      test::print_score("impacts 10s stereo, KLT on every point", scores_->impacts_klt);
    }
    auto dark_score = std::async(std::launch::async, [&] { return score("dark_room.yaml", dr); });
    scores_->vid18_hard = score("vid18_hard.yaml", v18);
    scores_->dark_room = dark_score.get();
    test::print_score("vid18_hard 8s stereo", scores_->vid18_hard);
    test::print_score("dark_room 8s stereo", scores_->dark_room);
  }
  static void TearDownTestSuite() { scores_.reset(); }

  void SetUp() override { ASSERT_TRUE(scores_->error.empty()) << scores_->error; }

  static inline std::unique_ptr<Scores> scores_;
};

TEST_F(HardImages, Vid18HardKeepsAHundredFeatures) {
  EXPECT_GE(scores_->vid18_hard.frames, 230u);
  EXPECT_GE(scores_->vid18_hard.median_features, 100.0);
}

TEST_F(HardImages, Vid18HardTrackErrorAgainstTrueProjection) {
  EXPECT_LE(scores_->vid18_hard.median_err_px, 0.3);
  EXPECT_LE(scores_->vid18_hard.drift_fraction, 0.01);
  EXPECT_LE(scores_->vid18_hard.median_disp_err_px, 0.3);
}

TEST_F(HardImages, DarkRoomKeepsAHundredFeatures) {
  EXPECT_GE(scores_->dark_room.frames, 230u);
  EXPECT_GE(scores_->dark_room.median_features, 100.0);
}

TEST_F(HardImages, DarkRoomTrackErrorAgainstTrueProjection) {
  EXPECT_LE(scores_->dark_room.median_err_px, 0.3);
  EXPECT_LE(scores_->dark_room.drift_fraction, 0.01);
  EXPECT_LE(scores_->dark_room.median_disp_err_px, 0.3);
}

TEST_F(HardImages, ImpactsDirectAlignmentKeepsAndPlacesTracksLikeKlt) {
  const test::TrackScore& d = scores_->impacts_direct;
  const test::TrackScore& k = scores_->impacts_klt;
  EXPECT_GE(d.frames, 290u);
  EXPECT_LE(d.median_err_px, 0.3);
  EXPECT_LE(d.median_err_px, k.median_err_px + 0.01);
  EXPECT_LE(d.drift_fraction, 0.01);
  EXPECT_GE(d.kept_fraction, k.kept_fraction - 0.005);
  EXPECT_GE(d.stereo_fraction, k.stereo_fraction - 0.02);
  EXPECT_LE(d.median_disp_err_px, 0.3);
}

}  // namespace
}  // namespace vid
