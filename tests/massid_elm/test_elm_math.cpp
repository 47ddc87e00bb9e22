/// @file test_elm_math.cpp
/// @brief ELM (Algorithm 1) and RELM (eq. 29) solvers on synthetic data.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <random>

#include "massid/elm/elm.h"

namespace vid::massid::elm {
namespace {

Eigen::MatrixXd random_inputs(int n, int d, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd X(n, d);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < d; ++j) X(i, j) = g(rng);
  return X;
}

/// Smooth nonlinear target of the inputs.
Eigen::VectorXd target_of(const Eigen::MatrixXd& X) {
  Eigen::VectorXd y(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    y(i) = std::sin(X(i, 0)) + 0.5 * X(i, 1) * X(i, 2) + 0.1 * X.row(i).squaredNorm();
  }
  return y;
}

TEST(HiddenLayer, SeededAndDeterministic) {
  const HiddenLayer a(4, 30, 7), b(4, 30, 7), c(4, 30, 8);
  EXPECT_EQ(a.weights(), b.weights());
  EXPECT_EQ(a.biases(), b.biases());
  EXPECT_GT((a.weights() - c.weights()).norm(), 1e-3);
  EXPECT_LE(a.weights().cwiseAbs().maxCoeff(), 1.0);
  // A larger layer starts with the smaller layer's nodes (nested hidden-node sweeps).
  const HiddenLayer big(4, 60, 7);
  EXPECT_EQ(big.weights().topRows(30), a.weights());
}

TEST(HiddenLayer, SigmoidOfAffineMap) {
  const HiddenLayer layer(3, 5, 3, 0.5);
  const Eigen::MatrixXd X = random_inputs(4, 3, 1);
  const Eigen::MatrixXd H = layer.activations(X);
  ASSERT_EQ(H.rows(), 4);
  ASSERT_EQ(H.cols(), 5);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 5; ++j) {
      const double z = layer.weights().row(j).dot(X.row(i)) + layer.biases()(j);
      EXPECT_NEAR(H(i, j), 1.0 / (1.0 + std::exp(-z)), 1e-15);
    }
    EXPECT_LT((layer.activation(X.row(i).transpose()) - H.row(i).transpose()).norm(), 1e-15);
  }
  EXPECT_THROW(layer.activations(random_inputs(2, 4, 1)), std::invalid_argument);
}

TEST(Elm, InterpolatesNDistinctSamplesWithNHiddenNodes) {
  // Huang's theorem behind Algorithm 1: N distinct samples, N hidden nodes -> H square and
  // (almost surely) invertible -> zero training error.
  for (int n : {20, 60, 150}) {
    const Eigen::MatrixXd X = random_inputs(n, 3, 10 + n);
    const Eigen::VectorXd y = target_of(X);
    const HiddenLayer layer(3, n, 42 + n, 2.0);
    const Eigen::MatrixXd H = layer.activations(X);
    const Eigen::MatrixXd beta = solve_elm(H, y);
    const double residual = (H * beta - y).norm();
    EXPECT_LT(residual, 1e-8) << "N = " << n;
  }
}

TEST(Elm, LeastSquaresMatchesNormalEquationsWhenOverdetermined) {
  const Eigen::MatrixXd X = random_inputs(400, 3, 2);
  const Eigen::VectorXd y = target_of(X);
  const Eigen::MatrixXd H = HiddenLayer(3, 20, 5).activations(X);
  const Eigen::MatrixXd beta = solve_elm(H, y);
  // Optimality: the residual is orthogonal to the columns of H.
  const Eigen::VectorXd g = H.transpose() * (H * beta - y);
  EXPECT_LT(g.norm(), 1e-9 * (H.norm() * y.norm()));
  // Same as the naive pseudo-inverse reference.
  const Eigen::MatrixXd beta_pinv = solve_elm_naive_pinv(H, y);
  EXPECT_LT((H * (beta - beta_pinv)).norm(), 1e-6 * y.norm());
}

TEST(Relm, SolvesRidgeNormalEquations) {
  const Eigen::MatrixXd X = random_inputs(300, 4, 3);
  const Eigen::VectorXd y = target_of(X);
  const Eigen::MatrixXd H = HiddenLayer(4, 50, 9).activations(X);
  const double lambda = 1e-3;
  const Eigen::MatrixXd beta = solve_relm(H, y, lambda);
  // Gradient of |H b - y|^2 + lambda |b|^2 vanishes.
  const Eigen::VectorXd grad = H.transpose() * (H * beta - y) + lambda * beta;
  EXPECT_LT(grad.norm(), 1e-9 * H.norm() * y.norm());
  const Eigen::MatrixXd beta_naive = solve_relm_naive_inverse(H, y, lambda);
  EXPECT_LT((beta - beta_naive).norm(), 1e-6 * beta.norm());
  EXPECT_THROW(solve_relm(H, y, 0.0), std::invalid_argument);
  EXPECT_THROW(solve_relm(H, y.head(10), lambda), std::invalid_argument);
}

TEST(Relm, WeightNormDecreasesAsLambdaGrows) {
  const Eigen::MatrixXd X = random_inputs(500, 4, 4);
  const Eigen::VectorXd y = target_of(X);
  const Eigen::MatrixXd H = HiddenLayer(4, 200, 11).activations(X);
  double previous = std::numeric_limits<double>::infinity();
  for (double lambda : {1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0}) {
    const double norm = solve_relm(H, y, lambda).norm();
    EXPECT_LT(norm, previous) << "lambda = " << lambda;
    previous = norm;
  }
  // And the unregularized ELM norm is larger than every ridge solution's.
  EXPECT_GT(solve_elm(H, y).norm(), solve_relm(H, y, 1e-7).norm());
}

TEST(Relm, RegularizedGramIsSymmetricAndShifted) {
  const Eigen::MatrixXd H = HiddenLayer(3, 10, 1).activations(random_inputs(30, 3, 5));
  const Eigen::MatrixXd G = regularized_gram(H, 0.25);
  Eigen::MatrixXd expected = H.transpose() * H;
  expected.diagonal().array() += 0.25;
  EXPECT_LT((G - expected).norm(), 1e-12 * expected.norm());
}

}  // namespace
}  // namespace vid::massid::elm
