/// @file test_oselm.cpp
/// @brief OSELM (Algorithm 2, eqs. 30-38) equals batch RELM (eq. 29) after all chunks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "massid/elm/elm.h"
#include "massid/elm/oselm.h"

namespace vid::massid::elm {
namespace {

struct Problem {
  Eigen::MatrixXd H;
  Eigen::MatrixXd T;
};

Problem make_problem(int n, int hidden, int outputs, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd X(n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 3; ++j) X(i, j) = g(rng);
  Problem p;
  p.H = HiddenLayer(3, hidden, seed + 1).activations(X);
  p.T.resize(n, outputs);
  for (int i = 0; i < n; ++i)
    for (int o = 0; o < outputs; ++o)
      p.T(i, o) = std::cos(X(i, 0) + o) + X(i, 1) * X(i, 2) + 0.05 * g(rng);
  return p;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

TEST(Oselm, FixedChunksAfterInitialBatchEqualBatchRelm) {
  const Problem p = make_problem(1200, 60, 1, 1);
  const double lambda = 1e-2;
  const Eigen::MatrixXd beta_batch = solve_relm(p.H, p.T, lambda);
  for (int chunk : {1, 7, 50}) {
    OnlineSequentialElm os(60, 1, lambda);
    os.initialize(p.H.topRows(150), p.T.topRows(150));
    for (int r = 150; r < p.H.rows(); r += chunk) {
      const int n = std::min<int>(chunk, static_cast<int>(p.H.rows()) - r);
      os.update(p.H.middleRows(r, n), p.T.middleRows(r, n));
    }
    EXPECT_EQ(os.samples(), p.H.rows());
    EXPECT_LT(relative(os.beta(), beta_batch), 1e-8) << "chunk " << chunk;
  }
}

TEST(Oselm, VaryingChunksFromRidgePriorEqualBatchRelmAfterEveryChunk) {
  const Problem p = make_problem(900, 40, 2, 2);
  const double lambda = 1e-1;
  OnlineSequentialElm os(40, 2, lambda);
  const int sizes[] = {1, 3, 17, 2, 64, 5};
  int r = 0;
  for (int k = 0; r < p.H.rows(); ++k) {
    const int n = std::min<int>(sizes[k % 6], static_cast<int>(p.H.rows()) - r);
    os.update(p.H.middleRows(r, n), p.T.middleRows(r, n));
    r += n;
    if (k % 10 == 9 || r == p.H.rows()) {
      // Recursive least squares: the weights after any prefix are that prefix's RELM.
      const Eigen::MatrixXd batch = solve_relm(p.H.topRows(r), p.T.topRows(r), lambda);
      EXPECT_LT(relative(os.beta(), batch), 1e-8) << "after " << r << " samples";
    }
  }
}

TEST(Oselm, RankOneUpdateEqualsChunkOfOne) {
  const Problem p = make_problem(300, 30, 1, 3);
  OnlineSequentialElm a(30, 1, 1e-2), b(30, 1, 1e-2);
  a.initialize(p.H.topRows(60), p.T.topRows(60));
  b.initialize(p.H.topRows(60), p.T.topRows(60));
  for (int r = 60; r < 300; ++r) {
    a.update(p.H.middleRows(r, 1), p.T.middleRows(r, 1));
    b.update_one(p.H.row(r).transpose(), p.T.row(r).transpose());
  }
  EXPECT_LT(relative(b.beta(), a.beta()), 1e-12);
  EXPECT_LT(relative(b.P(), a.P()), 1e-12);
}

TEST(Oselm, PIsInverseOfRegularizedGram) {
  const Problem p = make_problem(400, 25, 1, 4);
  OnlineSequentialElm os(25, 1, 0.5);
  os.initialize(p.H.topRows(100), p.T.topRows(100));
  os.update(p.H.bottomRows(300), p.T.bottomRows(300));
  const Eigen::MatrixXd G = regularized_gram(p.H, 0.5);
  EXPECT_LT((G * os.P() - Eigen::MatrixXd::Identity(25, 25)).norm(), 1e-9);
}

TEST(Oselm, ForgettingFactorMatchesExponentiallyWeightedRidge) {
  // With mu < 1 the recursion minimises sum mu^(n-i) |t_i - h_i b|^2 + mu^n lambda |b|^2.
  const Problem p = make_problem(500, 20, 1, 5);
  const double lambda = 1e-1, mu = 0.995;
  OnlineSequentialElm os(20, 1, lambda, mu);
  for (int r = 0; r < 500; ++r) os.update_one(p.H.row(r).transpose(), p.T.row(r).transpose());
  Eigen::VectorXd w(500);
  for (int i = 0; i < 500; ++i) w(i) = std::sqrt(std::pow(mu, 500 - 1 - i));
  const Eigen::MatrixXd Hw = w.asDiagonal() * p.H;
  const Eigen::MatrixXd Tw = w.asDiagonal() * p.T;
  const Eigen::MatrixXd expected = solve_relm(Hw, Tw, lambda * std::pow(mu, 500));
  EXPECT_LT(relative(os.beta(), expected), 1e-8);
  // The forgetting solver tracks a changed target faster than the plain one.
  OnlineSequentialElm plain(20, 1, lambda);
  for (int r = 0; r < 500; ++r) plain.update_one(p.H.row(r).transpose(), p.T.row(r).transpose());
  Eigen::MatrixXd shifted = p.T.array() + 1.0;
  for (int r = 0; r < 300; ++r) {
    os.update_one(p.H.row(r).transpose(), shifted.row(r).transpose());
    plain.update_one(p.H.row(r).transpose(), shifted.row(r).transpose());
  }
  // Prediction error on the most recent (shifted) samples.
  const Eigen::MatrixXd H_recent = p.H.middleRows(200, 100), T_recent = shifted.middleRows(200, 100);
  const double err_forgetting = (H_recent * os.beta() - T_recent).norm();
  const double err_plain = (H_recent * plain.beta() - T_recent).norm();
  EXPECT_LT(err_forgetting, err_plain);
}

TEST(Oselm, RejectsBadInput) {
  EXPECT_THROW(OnlineSequentialElm(10, 1, 0.0), std::invalid_argument);
  EXPECT_THROW(OnlineSequentialElm(10, 1, 1e-3, 1.5), std::invalid_argument);
  EXPECT_THROW(OnlineSequentialElm(10, 1, 1e-3, 0.0), std::invalid_argument);
  OnlineSequentialElm os(10, 1, 1e-3);
  EXPECT_THROW(os.update(Eigen::MatrixXd::Ones(2, 9), Eigen::MatrixXd::Ones(2, 1)),
               std::invalid_argument);
  os.update(Eigen::MatrixXd::Ones(2, 10), Eigen::MatrixXd::Ones(2, 1));
  EXPECT_THROW(os.initialize(Eigen::MatrixXd::Ones(2, 10), Eigen::MatrixXd::Ones(2, 1)),
               std::logic_error);
}

}  // namespace
}  // namespace vid::massid::elm
