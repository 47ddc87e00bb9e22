/// @file test_mass_model.cpp
/// @brief ELM / RELM / OSELM mass models on synthetic runs, split by run.
#include <gtest/gtest.h>

#include <cmath>

#include "massid/elm/mass_model.h"
#include "synthetic_run.h"

namespace vid::massid::elm {
namespace {

std::vector<MassIdRun> training_runs() {
  std::vector<MassIdRun> runs;
  const std::vector<std::function<double(double)>> profiles = {
      [](double) { return 1.5; },
      [](double t) { return 1.8 - 0.02 * t; },
      [](double t) { return t < 10.0 ? 1.6 : 1.3; },
      [](double t) { return t < 8.0 ? 1.3 : 1.7; },
      [](double t) { return 1.5 + 0.2 * std::sin(0.4 * t); }};
  unsigned seed = 10;
  for (const auto& m : profiles) {
    testing::SyntheticSpec spec;
    spec.mass = m;
    spec.sigma_v = 0.01;
    spec.seed = seed++;
    runs.push_back(testing::make_synthetic_run(spec));
  }
  return runs;
}

std::vector<const MassIdRun*> pointers(const std::vector<MassIdRun>& runs) {
  std::vector<const MassIdRun*> p;
  for (const auto& r : runs) p.push_back(&r);
  return p;
}

double held_out_rmspe(const MassModel& model, const MassIdRun& run) {
  const std::vector<double> m_hat = model.predict_run(run);
  std::vector<double> est, truth;
  for (size_t k = 100; k < run.samples.size(); ++k) {  // after 1 s: the windows are filled
    est.push_back(m_hat[k]);
    truth.push_back(run.samples[k].mass_true);
  }
  return rmspe(est, truth);
}

TEST(MassModel, RelmGeneralizesToHeldOutRun) {
  const auto runs = training_runs();
  testing::SyntheticSpec spec;
  spec.mass = [](double t) { return 1.45 + 0.1 * std::cos(0.3 * t); };
  spec.sigma_v = 0.01;
  spec.seed = 99;  // same trajectory as in training, new mass profile and noise (split by run)
  const MassIdRun test = testing::make_synthetic_run(spec);
  DataDrivenOptions options;
  options.hidden_nodes = 100;
  TrainStats stats;
  const auto model = MassModel::train(Method::kRelm, pointers(runs), options, {}, &stats);
  EXPECT_GT(stats.rows, 1500);
  EXPECT_LT(stats.train_rmse_percent, 1.0);
  const double rmspe_relm = held_out_rmspe(*model, test);
  EXPECT_LT(rmspe_relm, 1.0);
  // Far better than knowing only the training runs' mean mass.
  std::vector<double> mean_guess, truth;
  double mean_mass = 0.0;
  long n = 0;
  for (const auto& r : runs)
    for (const auto& x : r.samples) mean_mass += x.mass_true, ++n;
  mean_mass /= static_cast<double>(n);
  for (size_t k = 100; k < test.samples.size(); ++k) {
    mean_guess.push_back(mean_mass);
    truth.push_back(test.samples[k].mass_true);
  }
  EXPECT_LT(rmspe_relm, 0.2 * rmspe(mean_guess, truth));
}

TEST(MassModel, EstimatorMatchesBatchPrediction) {
  const auto runs = training_runs();
  DataDrivenOptions options;
  options.hidden_nodes = 50;
  for (const char* method : {"elm", "relm", "oselm"}) {
    const auto model = MassModel::train(parse_method(method), pointers(runs), options);
    ElmMassEstimator est(model);
    EXPECT_EQ(est.name(), method);
    const MassIdRun& run = runs[2];
    const std::vector<double> batch = model->predict_run(run);
    est.reset(run.info, run.samples[0]);
    for (size_t k = 0; k < run.samples.size(); ++k) {
      const double m = est.update(run.samples[k]);
      ASSERT_NEAR(m, batch[k], 1e-9 * batch[k]) << method << " sample " << k;
    }
    EXPECT_DOUBLE_EQ(batch[4], run.info.initial_mass_guess);  // 0.04 s: no window covered yet
    EXPECT_NE(batch[5], run.info.initial_mass_guess);         // 0.05 s: partial windows
  }
}

TEST(MassModel, OselmEqualsRelmOnTheSameData) {
  const auto runs = training_runs();
  DataDrivenOptions options;
  options.hidden_nodes = 80;
  options.lambda = 1e-3;
  options.oselm_chunk = 20;
  const auto relm = MassModel::train(Method::kRelm, pointers(runs), options);
  ModelConfig varying;
  varying.oselm_chunks = {1, 13, 40};
  const auto oselm = MassModel::train(Method::kOselm, pointers(runs), options, varying);
  EXPECT_LT((oselm->beta() - relm->beta()).norm() / relm->beta().norm(), 1e-8);
}

TEST(MassModel, TrainDataDrivenFactory) {
  const auto runs = training_runs();
  DataDrivenOptions options;
  options.hidden_nodes = 30;
  const auto est = train_data_driven("relm", pointers(runs), options);
  EXPECT_EQ(est->name(), "relm");
  EXPECT_THROW(train_data_driven("svm", pointers(runs), options), std::invalid_argument);
  EXPECT_THROW(train_data_driven("elm", {}, options), std::invalid_argument);
  options.lambda = 0.0;
  EXPECT_THROW(train_data_driven("relm", pointers(runs), options), std::invalid_argument);
}

}  // namespace
}  // namespace vid::massid::elm
