// Consistency on simulator data (issue acceptance): over 20 Monte-Carlo runs of a 60 s
// vid17_like feature-level sequence (seeds 1..20: trajectory, rope and sensor noise all
// differ), the run-averaged NEES of orientation, position and F_ext (3 dof each) stays inside
// the two-sided 95% band of the average of 20 chi2(3) for >= 90% of the time after 5 s, in
// both modes. The initial estimate is drawn from the initial covariance around the truth.
// The same in dynamics mode on rope_snap (a tether that snaps taut every lap, issue 17): the
// force-jump handling must keep the covariance honest through the snaps (not met: ratchets).
// Writes CSV (plot with `vid-eval nees`).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "consistency.h"
#include "ratchet.h"
#include "sim_system.h"

namespace {
using namespace vid;
using namespace vid::test;

constexpr int kRuns = 20;
constexpr double kDuration = 60.0;

double fraction_inside(const std::vector<double>& t, const std::vector<double>& v, double lo, double hi) {
  int n = 0, inside = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < 5.0) continue;
    ++n;
    inside += (v[i] >= lo && v[i] <= hi);
  }
  return n ? static_cast<double>(inside) / n : 0.0;
}

/// Fraction of the time after 5 s that the run-averaged NEES is inside the band, per block.
struct Inside {
  double theta = 0.0, p = 0.0, F = 0.0;
};

void run_mode(PropagationMode mode, const std::string& preset, Inside* inside) {
  NeesSeries avg;
  for (int k = 1; k <= kRuns; ++k) {
    const auto folder = ensure_sim_dataset(preset, k, kDuration);
    const NeesSeries s = nees_on_dataset(folder, mode, 5000 + k);
    ASSERT_EQ(s.status, "ok") << folder;
    if (avg.t.empty()) {
      avg.t = s.t;
      avg.theta.assign(s.t.size(), 0.0);
      avg.p = avg.F = avg.theta;
    }
    const std::size_t n = std::min(avg.t.size(), s.t.size());
    ASSERT_GE(n, static_cast<std::size_t>(kDuration * 10 - 20)) << folder;
    avg.t.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      avg.theta[i] += s.theta[i] / kRuns;
      avg.p[i] += s.p[i] / kRuns;
      avg.F[i] += s.F[i] / kRuns;
    }
  }
  avg.theta.resize(avg.t.size());
  avg.p.resize(avg.t.size());
  avg.F.resize(avg.t.size());
  const auto [lo, hi] = nees_band(kRuns);
  write_nees_csv(std::filesystem::path(VID_BINARY_DIR) / "vio_core_nees" / ("nees_" + preset + "_" + to_string(mode) + ".csv"),
                 kRuns, avg.t, avg.theta, avg.p, avg.F);
  inside->theta = fraction_inside(avg.t, avg.theta, lo, hi);
  inside->p = fraction_inside(avg.t, avg.p, lo, hi);
  inside->F = mode == PropagationMode::kDynamics ? fraction_inside(avg.t, avg.F, lo, hi) : 0.0;
  std::printf("%s %s: %d runs x %.0f s, band [%.2f, %.2f]; inside: theta %.3f, p %.3f, F %.3f\n", preset.c_str(),
              to_string(mode).c_str(), kRuns, kDuration, lo, hi, inside->theta, inside->p, inside->F);
}

TEST(NeesSim, Vid17LikeDynamicsMode) {
  Inside in;
  run_mode(PropagationMode::kDynamics, "vid17_like", &in);
  EXPECT_GE(in.theta, 0.9);
  EXPECT_GE(in.p, 0.9);
  EXPECT_GE(in.F, 0.9);
}

TEST(NeesSim, Vid17LikeImuMode) {
  Inside in;
  run_mode(PropagationMode::kImu, "vid17_like", &in);
  EXPECT_GE(in.theta, 0.9);
  EXPECT_GE(in.p, 0.9);
}

// Issue 17 acceptance, met for the attitude only. Measured 2026-11-28 (20 runs): inside the band
// theta 0.929, p 0.405, F 0.497 of the time (2026-11-25: 0.60, 0.27, 0.66): between a snap and
// its detection (10-60 ms) and along the tether's fast ramps (up to 15 m/s^3) the force model
// is wrong and the filter is overconfident in position and force. Ratchets at 0.8x today's
// fractions (a 20 % worse figure fails), next to the targets that are not met yet.
TEST(NeesSim, RopeSnapDynamicsMode) {
  Inside in;
  run_mode(PropagationMode::kDynamics, "rope_snap", &in);
  EXPECT_GE(in.theta, 0.9);
  expect_ratchet_at_least("rope_snap position NEES inside the band", in.p, 0.8 * 0.405, 0.405);
  expect_ratchet_at_least("rope_snap force NEES inside the band", in.F, 0.8 * 0.497, 0.497);
  expect_target_not_met_at_least("rope_snap position NEES inside the band", in.p, 0.9);
  expect_target_not_met_at_least("rope_snap force NEES inside the band", in.F, 0.9);
}

}  // namespace
