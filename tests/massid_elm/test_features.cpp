/// @file test_features.cpp
/// @brief Causal feature extraction and normalization (features.h).
#include <gtest/gtest.h>

#include "massid/elm/features.h"
#include "synthetic_run.h"

namespace vid::massid::elm {
namespace {

TEST(Features, DimensionAndLayout) {
  FeatureConfig c;
  EXPECT_EQ(c.dimension(), static_cast<int>(c.windows.size()) * 7 + 7);
  c.windows = {0.25, 0.5, 1.0};
  EXPECT_EQ(c.dimension(), 3 * 7 + 7);
  c.physics_ratio = false;
  EXPECT_EQ(c.dimension(), 3 * 6 + 7);
}

TEST(Features, WindowQuantitiesFollowIntegratedNewtonLaw) {
  testing::SyntheticSpec spec;
  spec.mass = [](double) { return 1.7; };
  const MassIdRun run = testing::make_synthetic_run(spec);
  FeatureConfig config;
  config.windows = {0.25, 0.5, 1.0};
  const RunFeatures f = extract_run_features(run, config, 1);
  // First feature row is the first sample at least 1 s (longest window) after the start.
  ASSERT_GT(f.X.rows(), 0);
  EXPECT_EQ(f.sample_index.front(), 100);
  EXPECT_EQ(f.X.rows(), static_cast<Eigen::Index>(run.samples.size()) - 100);
  for (Eigen::Index r = 0; r < f.X.rows(); r += 97) {
    const MassIdSample& s = run.samples[static_cast<size_t>(f.sample_index[static_cast<size_t>(r)])];
    for (int w = 0; w < 3; ++w) {
      const Eigen::Vector3d a_W = f.X.row(r).segment<3>(7 * w).transpose();
      const Eigen::Vector3d f_W = f.X.row(r).segment<3>(7 * w + 3).transpose();
      // m * mean specific acceleration == mean thrust vector (the synthetic run holds the
      // commands over each interval exactly like the extractor assumes).
      EXPECT_LT((1.7 * a_W - f_W).norm(), 1e-9 * f_W.norm()) << "row " << r << " window " << w;
      EXPECT_NEAR(f.X(r, 7 * w + 6), 1.7, 1e-9);
    }
    EXPECT_DOUBLE_EQ(f.X(r, 21), s.thrust_cmd);
    EXPECT_EQ(f.X.row(r).segment<3>(22).transpose(), s.w_I);
    EXPECT_LT((f.X.row(r).segment<3>(25).transpose() - s.q_WI * Eigen::Vector3d::UnitZ()).norm(), 1e-12);
    EXPECT_DOUBLE_EQ(f.y(r), 1.7);
  }
}

TEST(Features, CausalFutureSamplesDoNotChangeFeatures) {
  testing::SyntheticSpec spec;
  spec.sigma_v = 0.02;
  const MassIdRun run = testing::make_synthetic_run(spec);
  MassIdRun altered = run;
  for (size_t k = 800; k < altered.samples.size(); ++k) {
    altered.samples[k].v_WI *= 3.0;
    altered.samples[k].thrust_cmd += 5.0;
  }
  FeatureConfig config;
  config.windows = {0.25, 0.5, 1.0};
  const RunFeatures a = extract_run_features(run, config, 1);
  const RunFeatures b = extract_run_features(altered, config, 1);
  const Eigen::Index rows_before = 800 - 100;  // rows of samples 100..799
  EXPECT_EQ(a.X.topRows(rows_before), b.X.topRows(rows_before));
  EXPECT_NE(a.X.row(rows_before), b.X.row(rows_before));
}

TEST(Features, StreamingEqualsBatchAndStride) {
  testing::SyntheticSpec spec;
  spec.sigma_v = 0.01;
  const MassIdRun run = testing::make_synthetic_run(spec);
  FeatureConfig config;
  const RunFeatures every = extract_run_features(run, config, 1);
  const RunFeatures strided = extract_run_features(run, config, 5);
  ASSERT_EQ(strided.X.rows(), (every.X.rows() + 4) / 5);
  for (Eigen::Index r = 0; r < strided.X.rows(); ++r) {
    EXPECT_EQ(strided.X.row(r), every.X.row(5 * r));
  }
  FeatureExtractor ex(config);
  ex.reset(run.info.gravity);
  Eigen::VectorXd x;
  Eigen::Index row = 0;
  for (const MassIdSample& s : run.samples) {
    if (ex.push(s, &x)) {
      EXPECT_EQ(x.transpose(), every.X.row(row));
      ++row;
    }
  }
  EXPECT_EQ(row, every.X.rows());
}

TEST(Features, PartialWindowsBeforeTheLongestIsCovered) {
  testing::SyntheticSpec spec;
  spec.sigma_v = 0.01;
  const MassIdRun run = testing::make_synthetic_run(spec);
  const FeatureConfig config;  // 0.05 .. 0.4 s at 100 Hz
  const RunFeatures full = extract_run_features(run, config, 1);
  const RunFeatures partial = extract_run_features(run, config, 1, true);
  EXPECT_EQ(full.sample_index.front(), 40);
  EXPECT_EQ(partial.sample_index.front(), 5);
  const Eigen::Index offset = 40 - 5;
  ASSERT_EQ(partial.X.rows(), full.X.rows() + offset);
  EXPECT_EQ(partial.X.bottomRows(full.X.rows()), full.X);
  // At 0.2 s the 0.4 s window spans the 0.2 s since the first sample: same as the 0.2 s window.
  const Eigen::Index r = 20 - 5;
  EXPECT_EQ(partial.X.row(r).segment<7>(21), partial.X.row(r).segment<7>(14));
}

TEST(Features, RejectsBadConfigAndTime) {
  FeatureConfig c;
  c.windows = {0.5, 0.25};
  EXPECT_THROW(FeatureExtractor{c}, std::invalid_argument);
  c.windows = {};
  EXPECT_THROW(FeatureExtractor{c}, std::invalid_argument);
  FeatureExtractor ex;
  ex.reset(9.81);
  MassIdSample s;
  Eigen::VectorXd x;
  s.t = 1.0;
  EXPECT_FALSE(ex.push(s, &x));
  EXPECT_THROW(ex.push(s, &x), std::invalid_argument);
  EXPECT_THROW(extract_training_set({}, FeatureConfig{}), std::invalid_argument);
}

TEST(Features, NormalizerZeroMeanUnitStd) {
  Eigen::MatrixXd X(4, 3);
  X << 1, 5, 2, 2, 5, 4, 3, 5, 6, 4, 5, 8;
  const Eigen::VectorXd y = Eigen::Vector4d(1.0, 2.0, 3.0, 4.0);
  const Normalizer n = Normalizer::fit(X, y);
  const Eigen::MatrixXd Z = n.apply(X);
  EXPECT_LT(Z.colwise().mean().norm(), 1e-15);
  EXPECT_NEAR(std::sqrt(Z.col(0).squaredNorm() / 4.0), 1.0, 1e-14);
  EXPECT_EQ(Z.col(1), Eigen::Vector4d::Zero());  // constant column: std taken as 1
  EXPECT_LT((n.apply_row(X.row(2).transpose()) - Z.row(2).transpose()).norm(), 1e-15);
  const Eigen::VectorXd yn = n.apply_target(y);
  EXPECT_NEAR(n.invert_target(yn(3)), 4.0, 1e-14);
}

}  // namespace
}  // namespace vid::massid::elm
