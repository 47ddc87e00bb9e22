/// @file test_swls_batch.cpp
/// @brief SWLS (eqs. 18-23) with a window covering the whole sequence equals batch least
/// squares of the same cost, solved here independently by dense Gauss-Newton with numeric
/// Jacobians on the model's manifold (no Ceres, no marginalization code).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "massid/filters/swls.h"
#include "mini_sim.h"

namespace vid::massid {
namespace {

using Model = QuadrotorMassModel;

struct Batch {
  SwlsPriorResidual prior;
  std::vector<SwlsDynamicResidual> dyn;
  std::vector<SwlsMeasurementResidual> meas;
  int n = 0;

  int rows() const { return 10 + 10 * static_cast<int>(dyn.size()) + 9 * n; }
  Eigen::VectorXd residual(const std::vector<Model::State>& X) const {
    Eigen::VectorXd r(rows());
    std::vector<std::array<double, kSwlsAmbient>> a(n);
    for (int k = 0; k < n; ++k) swls_pack(X[k], a[k].data());
    int row = 0;
    prior(a[0].data(), r.data() + row);
    row += 10;
    for (int k = 0; k + 1 < n; ++k, row += 10) dyn[k](a[k].data(), a[k + 1].data(), r.data() + row);
    for (int k = 0; k < n; ++k, row += 9) meas[k](a[k].data(), r.data() + row);
    return r;
  }
};

std::vector<Model::State> gauss_newton(const Batch& b, std::vector<Model::State> X) {
  const int dim = 10 * b.n;
  for (int it = 0; it < 30; ++it) {
    const Eigen::VectorXd r0 = b.residual(X);
    Eigen::MatrixXd J(r0.size(), dim);
    const double h = 1e-7;
    for (int k = 0; k < b.n; ++k) {
      for (int j = 0; j < 10; ++j) {
        Model::StateVec d = Model::StateVec::Zero();
        d(j) = h;
        std::vector<Model::State> Xp = X, Xm = X;
        Xp[k] = Model::boxplus(X[k], d);
        Xm[k] = Model::boxplus(X[k], -d);
        J.col(10 * k + j) = (b.residual(Xp) - b.residual(Xm)) / (2 * h);
      }
    }
    const Eigen::VectorXd dx = (J.transpose() * J).ldlt().solve(-J.transpose() * r0);
    for (int k = 0; k < b.n; ++k) X[k] = Model::boxplus(X[k], dx.segment<10>(10 * k));
    if (dx.norm() < 1e-12) break;
  }
  return X;
}

TEST(SwlsBatch, FullWindowEqualsBatchLeastSquares) {
  test::MiniSimConfig cfg;
  cfg.duration_s = 0.3;  // 31 samples -> 310 unknowns
  cfg.sigma_v = 0.05;
  const MassIdRun run = test::simulate_loop(cfg);
  ModelBasedTuning tuning;
  tuning.swls_window = 1000;
  tuning.swls_max_iterations = 100;
  tuning.swls_function_tolerance = 1e-16;  // converge fully: compare optima, not stopping rules
  // The online step detector re-weights factors as samples arrive; the batch rebuild has no
  // online history, so compare the window machinery without it.
  tuning.mass_change_detection = false;
  SlidingWindowLs swls(tuning, run.info);
  for (const MassIdSample& s : run.samples) swls.add_sample(s);
  EXPECT_EQ(swls.marginalized(), 0);
  const std::vector<Model::State> window = swls.window_states();
  ASSERT_EQ(window.size(), run.samples.size());

  Batch b;
  b.n = static_cast<int>(run.samples.size());
  SlidingWindowLs::build_residuals(tuning, run.info, run.samples, &b.prior, &b.dyn, &b.meas);
  std::vector<Model::State> X0;
  for (const MassIdSample& s : run.samples) X0.push_back(initial_state(run.info, s));
  const std::vector<Model::State> X = gauss_newton(b, X0);
  // The batch optimum moved the mass away from the initial guess (the test has teeth).
  EXPECT_GT(std::abs(X.back().mass_kg - run.info.initial_mass_guess), 1e-3);
  for (int k = 0; k < b.n; ++k) {
    EXPECT_LT(Model::boxminus(window[k], X[k]).norm(), 1e-6) << "state " << k;
    EXPECT_NEAR(window[k].mass_kg, X[k].mass_kg, 1e-6 * X[k].mass_kg) << "state " << k;
  }
}

TEST(SwlsBatch, MarginalizationKeepsTheWindowBounded) {
  test::MiniSimConfig cfg;
  cfg.duration_s = 1.0;
  const MassIdRun run = test::simulate_loop(cfg);
  ModelBasedTuning tuning;
  tuning.swls_window = 8;
  SlidingWindowLs swls(tuning, run.info);
  for (const MassIdSample& s : run.samples) swls.add_sample(s);
  EXPECT_EQ(swls.window_states().size(), 8u);
  EXPECT_EQ(swls.marginalized(), static_cast<int>(run.samples.size()) - 8);
}

}  // namespace
}  // namespace vid::massid
