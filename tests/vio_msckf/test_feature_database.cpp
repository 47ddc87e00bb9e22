/// FeatureDatabase: input checks, lost / marginalization selection, clone-time filtering,
/// observation removal and bounded memory.

#include <gtest/gtest.h>

#include <algorithm>

#include "vio_core/msckf/feature_database.h"

namespace vid::msckf {
namespace {

constexpr TimeNs kDt = 50'000'000;

FeatureFrame frame(TimeNs t, const std::vector<std::uint64_t>& ids, bool stereo = false) {
  FeatureFrame f;
  f.t_ns = t;
  for (std::uint64_t id : ids) {
    for (int cam = stereo ? 1 : 0; cam >= 0; --cam) {  // cam 1 first: add() must sort
      FeatureObservation o;
      o.cam_id = cam;
      o.feature_id = id;
      o.uv_norm = Eigen::Vector2d(0.01 * static_cast<double>(id), 0.001 * static_cast<double>(t / kDt));
      o.has_norm = true;
      f.observations.push_back(o);
    }
  }
  return f;
}

std::vector<ClonePose> clones_at(const std::vector<TimeNs>& ts) {
  std::vector<ClonePose> c(ts.size());
  for (std::size_t i = 0; i < ts.size(); ++i) {
    c[i].t_ns = ts[i];
    c[i].cov_index = 15 + 6 * static_cast<int>(i);
  }
  return c;
}

const FeatureTrack* find(const std::vector<FeatureTrack>& v, std::uint64_t id) {
  for (const auto& t : v) {
    if (t.feature_id == id) return &t;
  }
  return nullptr;
}

TEST(FeatureDatabase, RejectsObservationsWithoutNormalizedCoordinates) {
  FeatureDatabase db;
  FeatureFrame f = frame(kDt, {1, 2});
  f.observations[1].has_norm = false;
  EXPECT_THROW(db.add(f), std::invalid_argument);
  EXPECT_EQ(db.num_tracks(), 0u);  // nothing half-added
  db.add(frame(2 * kDt, {1}));
  EXPECT_THROW(db.add(frame(kDt, {1})), std::invalid_argument);  // out of order
}

TEST(FeatureDatabase, SelectsLostTracksAndKeepsTrackedOnes) {
  FeatureDatabase db;
  db.add(frame(1 * kDt, {1, 2, 3}, true));
  db.add(frame(2 * kDt, {1, 2, 3}, true));
  db.add(frame(3 * kDt, {1, 3}, true));  // 2 lost
  EXPECT_EQ(db.num_tracks(), 3u);
  EXPECT_EQ(db.num_observations(), 2u * 8u);

  const auto clones = clones_at({1 * kDt, 2 * kDt, 3 * kDt});
  const auto sel = db.select_for_update(clones, 3 * kDt, /*window_full=*/false);
  ASSERT_EQ(sel.size(), 1u);
  EXPECT_EQ(sel[0].feature_id, 2u);
  ASSERT_EQ(sel[0].obs.size(), 4u);
  // Sorted by (t, cam).
  EXPECT_EQ(sel[0].obs[0].t_ns, kDt);
  EXPECT_EQ(sel[0].obs[0].cam_id, 0);
  EXPECT_EQ(sel[0].obs[1].cam_id, 1);
  EXPECT_EQ(sel[0].obs[3].t_ns, 2 * kDt);
  EXPECT_DOUBLE_EQ(sel[0].obs[3].uv_norm.x(), 0.02);
  // Removed; the others stay.
  EXPECT_EQ(db.num_tracks(), 2u);
  EXPECT_TRUE(db.select_for_update(clones, 3 * kDt, false).empty());
}

TEST(FeatureDatabase, WindowFullSelectsTracksSeenByOldestClone) {
  FeatureDatabase db;
  db.add(frame(1 * kDt, {1, 2}));
  db.add(frame(2 * kDt, {1, 2, 3}));
  db.add(frame(3 * kDt, {1, 2, 3}));
  const auto clones = clones_at({3 * kDt, 1 * kDt, 2 * kDt});  // order must not matter
  EXPECT_TRUE(db.select_for_update(clones, 3 * kDt, false).empty());
  const auto sel = db.select_for_update(clones, 3 * kDt, true);
  ASSERT_EQ(sel.size(), 2u);
  EXPECT_NE(find(sel, 1), nullptr);
  EXPECT_NE(find(sel, 2), nullptr);
  EXPECT_EQ(find(sel, 1)->obs.size(), 3u);
  EXPECT_EQ(db.num_tracks(), 1u);  // feature 3 (not seen by the oldest clone) stays
}

TEST(FeatureDatabase, IgnoresObservationsAtNonCloneTimes) {
  FeatureDatabase db;
  for (int k = 1; k <= 5; ++k) db.add(frame(k * kDt, {7}));
  db.add(frame(6 * kDt, {8}));
  // Only frames 2 and 4 were cloned; the track is lost at 6.
  const auto sel = db.select_for_update(clones_at({2 * kDt, 4 * kDt, 6 * kDt}), 6 * kDt, false);
  ASSERT_EQ(sel.size(), 1u);
  ASSERT_EQ(sel[0].obs.size(), 2u);
  EXPECT_EQ(sel[0].obs[0].t_ns, 2 * kDt);
  EXPECT_EQ(sel[0].obs[1].t_ns, 4 * kDt);
}

TEST(FeatureDatabase, PrunesObservationsOlderThanWindowAndMarginalizedClones) {
  FeatureDatabase db;
  for (int k = 1; k <= 4; ++k) db.add(frame(k * kDt, {1, 2}));
  EXPECT_EQ(db.num_observations(), 8u);
  // Window now starts at 3: observations at 1, 2 are useless and dropped.
  EXPECT_TRUE(db.select_for_update(clones_at({3 * kDt, 4 * kDt}), 4 * kDt, false).empty());
  EXPECT_EQ(db.num_observations(), 4u);
  db.remove_observations_at(3 * kDt);
  EXPECT_EQ(db.num_observations(), 2u);
  db.remove_observations_at(4 * kDt);
  EXPECT_EQ(db.num_tracks(), 0u);  // empty tracks are dropped
}

TEST(FeatureDatabase, MemoryIsBounded) {
  FeatureDatabase db(/*max_track_age_ns=*/3 * kDt, /*max_tracks=*/50);
  // Without selection calls, old tracks go stale and the total is capped.
  for (int k = 1; k <= 100; ++k) {
    std::vector<std::uint64_t> ids;
    for (int j = 0; j < 30; ++j) ids.push_back(static_cast<std::uint64_t>(1000 * k + j));
    db.add(frame(k * kDt, ids));
    EXPECT_LE(db.num_tracks(), 50u);
  }
  EXPECT_GT(db.num_dropped(), 0u);
  EXPECT_LE(db.num_observations(), 50u);
  // The newest tracks survive the cap.
  const auto sel = db.select_for_update(clones_at({100 * kDt}), 101 * kDt, false);
  EXPECT_NE(find(sel, 100 * 1000 + 5), nullptr);
}

TEST(FeatureDatabase, DuplicateObservationsAreCountedNotStored) {
  FeatureDatabase db;
  FeatureFrame f = frame(kDt, {1});
  f.observations.push_back(f.observations[0]);
  db.add(f);
  EXPECT_EQ(db.num_observations(), 1u);
  EXPECT_EQ(db.num_duplicates(), 1u);
}

}  // namespace
}  // namespace vid::msckf
