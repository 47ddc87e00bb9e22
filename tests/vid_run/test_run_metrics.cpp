/// vid_run's own metrics (summary.json): association, posyaw ATE, force RMSE, mass, stats.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "runner/run_metrics.h"
#include "runner/run_summary.h"

namespace vid::runner {
namespace {

TEST(Association, NearestWithinToleranceTiesToEarlier) {
  const std::vector<TimeNs> est{100, 200, 300, 1000};
  const std::vector<TimeNs> gt{90, 150, 250, 310, 5000};
  // gt is longer: walk est. 100->90, 200->150 (tie 150/250 goes to the earlier), 300->310, 1000 none.
  const auto p = associate_nearest(est, gt, 60);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0], (std::pair<std::size_t, std::size_t>{0, 0}));
  EXPECT_EQ(p[1], (std::pair<std::size_t, std::size_t>{1, 1}));
  EXPECT_EQ(p[2], (std::pair<std::size_t, std::size_t>{2, 3}));
  // est longer than gt: walk gt, pairs are still (est, gt).
  const auto q = associate_nearest(gt, est, 60);
  ASSERT_EQ(q.size(), 3u);
  EXPECT_EQ(q[0], (std::pair<std::size_t, std::size_t>{0, 0}));
}

Vec3Series random_path(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  Vec3Series s;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    p += 0.05 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    s.t_ns.push_back(1'000'000'000 + static_cast<TimeNs>(i) * 5'000'000);
    s.v.push_back(p);
  }
  return s;
}

TEST(Ate, RecoversYawAndTranslationExactly) {
  const Vec3Series gt = random_path(500, 1);
  Vec3Series est = gt;
  const Eigen::AngleAxisd yaw(0.7, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d t(1.0, -2.0, 0.5);
  for (auto& v : est.v) v = yaw * v + t;  // est = yaw * gt + t  ->  alignment inverts it
  const auto r = ate_posyaw(est, gt);
  ASSERT_TRUE(r.has_value());
  EXPECT_LT(r->rmse_m, 1e-10);
  EXPECT_NEAR(r->yaw_rad, -0.7, 1e-10);
  EXPECT_EQ(r->pairs, 500u);
}

TEST(Ate, RollIsNotAlignedAway) {
  // posyaw alignment must not absorb a roll error (only yaw + translation are free).
  const Vec3Series gt = random_path(500, 2);
  Vec3Series est = gt;
  const Eigen::AngleAxisd roll(0.1, Eigen::Vector3d::UnitX());
  for (auto& v : est.v) v = roll * v;
  const auto r = ate_posyaw(est, gt);
  ASSERT_TRUE(r.has_value());
  EXPECT_GT(r->rmse_m, 1e-3);
}

TEST(Ate, KnownOffsetNoise) {
  // A constant offset is absorbed; an alternating +-d z error (zero mean) gives RMSE d.
  const Vec3Series gt = random_path(400, 3);
  Vec3Series est = gt;
  for (std::size_t i = 0; i < est.v.size(); ++i) est.v[i] += Eigen::Vector3d(3, 3, (i % 2 == 0) ? 0.02 : -0.02);
  const auto r = ate_posyaw(est, gt);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->rmse_m, 0.02, 1e-4);
  EXPECT_FALSE(ate_posyaw(Vec3Series{}, gt).has_value());
}

TEST(ForceRmse, NormOfErrorOverPairs) {
  Vec3Series est, gt;
  for (int i = 0; i < 10; ++i) {
    est.t_ns.push_back(i * 10'000'000LL);
    gt.t_ns.push_back(i * 10'000'000LL + 1'000'000);  // 1 ms offset: all associate
    gt.v.emplace_back(1.0 * i, 0.0, 0.0);
    est.v.push_back(gt.v.back() + Eigen::Vector3d(0.0, 0.3, 0.4));  // |error| = 0.5
  }
  std::size_t pairs = 0;
  const auto r = force_rmse(est, gt, &pairs);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(*r, 0.5, 1e-12);
  EXPECT_EQ(pairs, 10u);
}

TEST(Mass, InterpolatesAndHolds) {
  const std::vector<TimeNs> t{100, 200};
  const std::vector<double> m{3.0, 4.0};
  EXPECT_DOUBLE_EQ(mass_at(t, m, 50), 3.0);
  EXPECT_DOUBLE_EQ(mass_at(t, m, 150), 3.5);
  EXPECT_DOUBLE_EQ(mass_at(t, m, 500), 4.0);
}

TEST(StageStats, NearestRankQuantiles) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // unsorted input
  const auto j = stage_stats(v);
  EXPECT_EQ(j["count"].get<int>(), 100);
  EXPECT_DOUBLE_EQ(j["median_ms"].get<double>(), 50.0);
  EXPECT_DOUBLE_EQ(j["p99_ms"].get<double>(), 99.0);
  EXPECT_DOUBLE_EQ(j["max_ms"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(j["mean_ms"].get<double>(), 50.5);
  EXPECT_EQ(stage_stats({})["count"].get<int>(), 0);
}

}  // namespace
}  // namespace vid::runner
