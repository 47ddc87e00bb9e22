// Consistency: Monte-Carlo averaged NEES of orientation, position and F_ext (3 dof each) on
// analytic synthetic flights, both modes. Initial estimates are drawn from the initial
// covariance. Writes CSV (plot with `vid-eval nees`).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "consistency.h"
#include "ratchet.h"
#include "run_helpers.h"

namespace {
using namespace vid;
using namespace vid::test;

bool ci() {
  const char* v = std::getenv("CI");
  return v != nullptr && std::string(v) == "true";
}

struct NeesCurves {
  std::vector<double> t, theta, p, F;
};

NeesCurves monte_carlo(PropagationMode mode, int runs, double duration) {
  NeesCurves c;
  for (int k = 0; k < runs; ++k) {
    SynthConfig sc;
    sc.duration = duration;
    sc.noisy = true;
    sc.seed = 100 + k;
    const SynthData d = generate(sc);
    const RunResult r = run_estimator(sc, d, matching_config(sc, d, mode), true, 1000 + k);
    EXPECT_EQ(r.status, FilterStatus::kOk) << r.message;
    if (k == 0) {
      for (const RunError& e : r.errors) c.t.push_back(e.t);
      c.theta.assign(c.t.size(), 0.0);
      c.p = c.theta;
      c.F = c.theta;
    }
    EXPECT_EQ(r.errors.size(), c.t.size());
    for (std::size_t i = 0; i < std::min(c.t.size(), r.errors.size()); ++i) {
      const RunError& e = r.errors[i];
      c.theta[i] += e.e_theta.dot(e.P_theta.ldlt().solve(e.e_theta)) / runs;
      c.p[i] += e.e_p.dot(e.P_p.ldlt().solve(e.e_p)) / runs;
      if (mode == PropagationMode::kDynamics) c.F[i] += e.e_F_I.dot(e.P_F.ldlt().solve(e.e_F_I)) / runs;
    }
  }
  return c;
}

struct Fractions {
  double inside = 0, below_upper = 0, mean = 0;  // mean: the time-average of the NEES after 5 s
};

Fractions fractions(const std::vector<double>& t, const std::vector<double>& v, double lo, double hi) {
  Fractions f;
  int n = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] < 5.0) continue;
    ++n;
    f.inside += (v[i] >= lo && v[i] <= hi);
    f.below_upper += (v[i] <= hi);
    f.mean += v[i];
  }
  f.inside /= n;
  f.below_upper /= n;
  f.mean /= n;
  return f;
}

void run_mode(PropagationMode mode) {
  const int runs = ci() ? 10 : 20;
  const double duration = 15.0;
  const NeesCurves c = monte_carlo(mode, runs, duration);
  const auto [lo, hi] = nees_band(runs);
  write_nees_csv(std::filesystem::path(VID_BINARY_DIR) / "vio_core_nees" / ("nees_synthetic_" + to_string(mode) + ".csv"),
                 runs, c.t, c.theta, c.p, c.F, 4);
  const Fractions th = fractions(c.t, c.theta, lo, hi);
  const Fractions p = fractions(c.t, c.p, lo, hi);
  std::printf("%s: %d runs, band [%.2f, %.2f]; inside band: theta %.3f, p %.3f", to_string(mode).c_str(),
              runs, lo, hi, th.inside, p.inside);
  EXPECT_GE(th.inside, 0.9);
  EXPECT_GE(p.inside, 0.9);
  if (mode == PropagationMode::kDynamics) {
    const Fractions F = fractions(c.t, c.F, lo, hi);
    std::printf(", F %.3f (not above the band: %.3f)\n", F.inside, F.below_upper);
    // F_ext is modelled as a random walk while the true force is smooth: the filter is
    // conservative (NEES below the band, in it ~1-30 % of the time) and must not be
    // overconfident. One-sided, a force sigma grown 2x passed; so the time-mean of the F NEES
    // is held two-sided at today's value: measured (182d56e) 1.54 over 10 runs (CI), 1.49 over
    // 20, where 3 is consistent; band today / 1.2 .. today x 1.2 (a 10 % larger or smaller
    // sigma moves the mean by ~20 %; the 10- vs 20-run values differ by 3 %).
    EXPECT_GE(F.below_upper, 0.9);
    const double F_mean = runs == 10 ? 1.54 : 1.49;
    expect_in_band("F NEES time-mean after 5 s", F.mean, F_mean / 1.2, F_mean * 1.2);
  }
  std::printf("\n");
}

TEST(NeesSynthetic, DynamicsMode) { run_mode(PropagationMode::kDynamics); }
TEST(NeesSynthetic, ImuMode) { run_mode(PropagationMode::kImu); }

}  // namespace
