// Fixed-lag smoothing in the estimator (docs/notes/smoothing.md) on analytic
// synthetic sequences: the causal estimates are those of the filter without force clones (to
// 1e-9), every causal estimate comes out smoothed once, the smoothed force covariance is at most
// the causal one, and over a Monte-Carlo of seeds the smoothed force is more accurate and its
// NEES no less consistent than the causal one's.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <map>

#include "run_helpers.h"

namespace {
using namespace vid;
using namespace vid::test;

struct SmootherRun {
  std::vector<EstimateOutput> causal, smoothed;
  FilterStatus status = FilterStatus::kOk;
};

SmootherRun run(const SynthConfig& c, const SynthData& d, const EstimatorConfig& pc, unsigned init_seed) {
  Estimator estimator(pc);
  SmootherRun out;
  estimator.set_estimate_callback([&](const EstimateOutput& e) { out.causal.push_back(e); });
  estimator.set_smoothed_callback([&](const EstimateOutput& e) { out.smoothed.push_back(e); });
  ImuState x0 = initial_state(c);
  const Eigen::MatrixXd P0 = initial_covariance(pc.params, x0.T_WI.q);
  x0.b_g = c.b_g;
  x0.b_a = c.b_a;
  perturb_by_covariance(x0, P0, init_seed);
  estimator.initialize(0, x0, P0);
  for (const Measurement& m : d.stream) estimator.push(m);
  estimator.finish();
  out.status = estimator.status();
  return out;
}

SynthConfig noisy_config(unsigned seed) {
  SynthConfig c;
  c.duration = 6.0;
  c.noisy = true;
  c.seed = seed;
  c.force_amplitude = 1.5;
  return c;
}

TEST(EstimatorSmoother, CausalEstimatesUnchangedAndEverySmoothedOnce) {
  const SynthConfig c = noisy_config(4);
  const SynthData d = generate(c);
  const EstimatorConfig plain = matching_config(c, d, PropagationMode::kDynamics);
  EstimatorConfig lagged = plain;
  lagged.params.smoother_lag_s = 0.3;
  lagged.params.smoother_clone_period_s = 0.1;
  const SmootherRun a = run(c, d, plain, 7), b = run(c, d, lagged, 7);
  ASSERT_EQ(a.status, FilterStatus::kOk);
  ASSERT_EQ(b.status, FilterStatus::kOk);
  EXPECT_TRUE(a.smoothed.empty());
  ASSERT_EQ(a.causal.size(), b.causal.size());
  ASSERT_GT(a.causal.size(), 2000u);
  double worst = 0.0;
  for (std::size_t i = 0; i < a.causal.size(); ++i) {
    const EstimateOutput &x = a.causal[i], &y = b.causal[i];
    ASSERT_EQ(x.t_ns, y.t_ns);
    worst = std::max({worst, so3::boxminus(x.x.T_WI.q, y.x.T_WI.q).norm(), (x.x.T_WI.p - y.x.T_WI.p).norm(),
                      (x.x.v_WI - y.x.v_WI).norm(), (x.x.b_a - y.x.b_a).norm(), (x.F_ext_W - y.F_ext_W).norm(),
                      (x.cov_F_W - y.cov_F_W).cwiseAbs().maxCoeff(), (x.sigma - y.sigma).cwiseAbs().maxCoeff()});
  }
  std::printf("causal with vs without force clones: largest difference %.3g\n", worst);
  EXPECT_LT(worst, 1e-9);
  // Every causal estimate once, in order, smoothed.
  ASSERT_EQ(b.smoothed.size(), b.causal.size());
  int moved = 0;
  for (std::size_t i = 0; i < b.causal.size(); ++i) {
    ASSERT_EQ(b.smoothed[i].t_ns, b.causal[i].t_ns);
    // The smoothed force covariance is at most the causal one (eq. S6).
    const Eigen::Matrix3d dP = b.causal[i].cov_F_W - b.smoothed[i].cov_F_W;
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(dP).eigenvalues().minCoeff(), -1e-12) << i;
    if ((b.smoothed[i].F_ext_W - b.causal[i].F_ext_W).norm() > 1e-6) ++moved;
  }
  EXPECT_GT(moved, static_cast<int>(b.causal.size()) / 2);
}

TEST(EstimatorSmoother, SmoothedForceMoreAccurateAndConsistentOverSeeds) {
  constexpr int kRuns = 6;
  double se_causal = 0, se_smooth = 0, nees_causal = 0, nees_smooth = 0;
  long n = 0;
  for (int run_i = 0; run_i < kRuns; ++run_i) {
    const SynthConfig c = noisy_config(20 + run_i);
    const SynthData d = generate(c);
    EstimatorConfig pc = matching_config(c, d, PropagationMode::kDynamics);
    pc.params.smoother_lag_s = 0.3;
    const SmootherRun r = run(c, d, pc, 100 + run_i);
    ASSERT_EQ(r.status, FilterStatus::kOk);
    ASSERT_EQ(r.smoothed.size(), r.causal.size());
    std::map<TimeNs, const TruthState*> truth;
    for (const TruthState& s : d.truth) truth[s.t_ns] = &s;
    for (std::size_t i = 0; i < r.causal.size(); ++i) {
      const auto it = truth.find(r.causal[i].t_ns);
      if (it == truth.end() || ns_to_s(r.causal[i].t_ns) < 1.0) continue;
      const Eigen::Vector3d ec = r.causal[i].F_ext_W - it->second->F_W;
      const Eigen::Vector3d es = r.smoothed[i].F_ext_W - it->second->F_W;
      se_causal += ec.squaredNorm();
      se_smooth += es.squaredNorm();
      nees_causal += ec.dot(r.causal[i].cov_F_W.ldlt().solve(ec));
      nees_smooth += es.dot(r.smoothed[i].cov_F_W.ldlt().solve(es));
      ++n;
    }
  }
  ASSERT_GT(n, 0);
  const double rmse_c = std::sqrt(se_causal / n), rmse_s = std::sqrt(se_smooth / n);
  const double nc = nees_causal / n, ns = nees_smooth / n;
  std::printf("force RMSE causal %.4f smoothed %.4f m/s^2; mean F_W NEES causal %.2f smoothed %.2f (3 expected)\n",
              rmse_c, rmse_s, nc, ns);
  EXPECT_LT(rmse_s, 0.8 * rmse_c);
  // No more overconfident than the causal filter, whose consistency the NEES suites check.
  EXPECT_LT(ns, std::max(nc, 3.0) * 1.25);
}

}  // namespace
