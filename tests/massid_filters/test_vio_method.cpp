/// @file test_vio_method.cpp
/// @brief The study method "vio" (vio_core's estimator on the study's data) on runs of the
/// study's own generator: it runs through the runner, names itself, and its RMSPE is held at
/// today's value (ratchet, docs/testing.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../vio_core/ratchet.h"
#include "massid/filters/estimators.h"
#include "massid/filters/study_runner.h"
#include "massid/filters/vio_filter.h"
#include "massid/gen/run_simulator.h"

namespace vid::massid {
namespace {

/// RMSPE [%] of "vio" on run 0 of the study generator's trajectory x profile, shortened.
double vio_rmspe(const std::string& trajectory, const std::string& profile, double duration_s, int index = 0) {
  gen::GeneratorSettings s;
  s.duration_s = duration_s;
  const MassIdRun run =
      gen::simulate_run(s, trajectory, profile, index, gen::run_seed(s.seed, trajectory, profile, index)).run;
  auto est = make_model_based_estimator("vio");
  EXPECT_EQ(est->name(), "vio");
  const RunResult r = evaluate_run(run, {est.get()});
  EXPECT_EQ(r.methods.size(), 1u);
  for (double m : r.methods[0].mass_hat) EXPECT_TRUE(std::isfinite(m));
  return r.methods[0].rmspe_pct;
}

TEST(VioMethod, IsAStudyMethod) {
  const auto methods = available_methods();
  EXPECT_NE(std::find(methods.begin(), methods.end(), "vio"), methods.end());
  EXPECT_THROW(make_vio_estimator(EstimatorParams{}), std::invalid_argument);  // no thrust scale
}

TEST(VioMethod, RmspeOnGeneratedLoopRuns) {
  // Measured on h50-vio (vio_params_for_study()), 12 s runs 0-4 of the study generator:
  // constant 3.41 / 3.30 / 2.63 / 1.85 / 3.12 %, step_drop 28.8 / 27.6 / 29.3 / 16.8 / 25.6 %.
  // The seeds spread > 20 %, so run 0 is held at 1.2 x its own value (docs/testing.md).
  const double constant = vio_rmspe("loop", "constant", 12.0);
  const double step_drop = vio_rmspe("loop", "step_drop", 12.0);
  test::expect_ratchet("vio RMSPE loop/constant 12 s run 0 [%]", constant, 4.09, 3.41);
  test::expect_ratchet("vio RMSPE loop/step_drop 12 s run 0 [%]", step_drop, 34.5, 28.8);
  // Target: the seed's study RMSPE range, 0.5-2.4 % (docs/design.md §5), which ekf, ukf and
  // swls meet. Not met: the body-frame force random walk takes the mass change, and at a step
  // the controller's own thrust response makes the force/scale split go the wrong way
  // (dynamics/massid/README.md "VIO").
  test::expect_target_not_met("vio RMSPE loop/constant 12 s run 0 [%]", constant, 2.4);
  test::expect_target_not_met("vio RMSPE loop/step_drop 12 s run 0 [%]", step_drop, 2.4);
}

}  // namespace
}  // namespace vid::massid
