/// vid_run's own metrics (summary.json): association, posyaw ATE, force RMSE, mass, stats.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "vid_system/metrics.h"
#include "vid_system/summary.h"

namespace vid::system {
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

// The estimator's world has its own heading: the force compared after rotating it by the
// ATE's yaw equals the error in the ground truth's world, at any heading.
TEST(ForceRmse, GaugeRemovedByTheAteYaw) {
  const Vec3Series gt_p = random_path(400, 11);
  const double heading = 165.0 * M_PI / 180.0;
  const Eigen::Matrix3d R_EG = Eigen::AngleAxisd(-heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Vec3Series est_p = gt_p, gt_f, est_f;
  const Eigen::Vector3d err_G(0.1, -0.2, 0.05);
  for (std::size_t i = 0; i < gt_p.t_ns.size(); ++i) {
    est_p.v[i] = R_EG * gt_p.v[i] + Eigen::Vector3d(2.0, -1.0, 0.3);
    const double t = 0.01 * static_cast<double>(i);
    gt_f.t_ns.push_back(gt_p.t_ns[i]);
    gt_f.v.emplace_back(std::sin(t), 2.0 * std::cos(0.3 * t), -0.5);
    est_f.t_ns.push_back(gt_p.t_ns[i]);
    est_f.v.push_back(R_EG * (gt_f.v.back() + err_G));
  }
  const auto ate = ate_posyaw(est_p, gt_p);
  ASSERT_TRUE(ate.has_value());
  EXPECT_NEAR(std::remainder(ate->yaw_rad - heading, 2.0 * M_PI), 0.0, 1e-9);
  const auto aligned = force_rmse(rotate_about_z(est_f, ate->yaw_rad), gt_f);
  ASSERT_TRUE(aligned.has_value());
  EXPECT_NEAR(*aligned, err_G.norm(), 1e-9);
  EXPECT_GT(*force_rmse(est_f, gt_f), 5.0 * err_G.norm()) << "unaligned, the gauge dominates";
}

TEST(ForceRmse, WorldToBodyUsesTheNearestOrientation) {
  Vec3Series f_W;
  std::vector<TimeNs> t_R;
  std::vector<Eigen::Matrix3d> R_WI;
  for (int i = 0; i < 5; ++i) {
    f_W.t_ns.push_back(i * 20'000'000LL);
    f_W.v.emplace_back(1.0, 0.0, 0.0);
    t_R.push_back(i * 20'000'000LL + 2'000'000);
    R_WI.push_back(Eigen::AngleAxisd(0.5 * M_PI * i, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  }
  t_R.back() += 50'000'000;  // no orientation within 10 ms of the last force: it is dropped
  const Vec3Series f_I = world_to_body(f_W, t_R, R_WI);
  ASSERT_EQ(f_I.t_ns.size(), 4u);
  EXPECT_LT((f_I.v[1] - Eigen::Vector3d(0.0, -1.0, 0.0)).norm(), 1e-12);  // R_WI^T x_W, yaw 90 deg
  EXPECT_LT((f_I.v[2] - Eigen::Vector3d(-1.0, 0.0, 0.0)).norm(), 1e-12);
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

// Past kExactSamples the statistics come from the histogram: quantiles within the stated
// relative error of the exact nearest-rank ones, count / mean / max exact (a one-hour live run).
TEST(StageStats, LongRunsStayWithinTheRelativeError) {
  std::mt19937_64 rng(7);
  std::lognormal_distribution<double> ms(std::log(3.0), 0.6);
  StageStats s;
  std::vector<double> all;
  for (int i = 0; i < 200000; ++i) {
    const double v = i % 5000 == 0 ? 0.0 : ms(rng);  // a few zero-duration stages too
    s.add(v);
    all.push_back(v);
  }
  std::sort(all.begin(), all.end());
  const auto exact = [&](double q) { return all[static_cast<std::size_t>(std::ceil(q * all.size())) - 1]; };
  const auto j = s.to_json();
  EXPECT_EQ(j["count"].get<std::size_t>(), all.size());
  EXPECT_DOUBLE_EQ(j["max_ms"].get<double>(), all.back());
  EXPECT_NEAR(j["mean_ms"].get<double>(), std::accumulate(all.begin(), all.end(), 0.0) / all.size(), 1e-9);
  for (double q : {0.01, 0.5, 0.9, 0.99, 0.999}) {
    EXPECT_NEAR(s.quantile(q), exact(q), StageStats::kRelativeError * exact(q)) << q;
    EXPECT_NE(s.quantile(q), exact(q)) << "the histogram is in use";  // not the exact path
  }
  EXPECT_DOUBLE_EQ(s.quantile(0.0001), 0.0);  // the zeros: clamped to the exact minimum
}

}  // namespace
}  // namespace vid::system
