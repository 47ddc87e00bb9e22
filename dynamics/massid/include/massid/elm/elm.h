#pragma once
/// @file elm.h
/// @brief Extreme learning machine (seed section 4.2.5, Algorithm 1) and its regularized
/// form RELM (docs/model.md eq. (60)): one hidden layer of sigmoid nodes with seeded random input
/// weights and biases, output weights by linear least squares.
///
/// Notation (seed): inputs X (N x d, one sample per row), hidden-layer output
/// H = g(X W^T + 1 b^T) (N x L, g = sigmoid), targets T (N x m), output weights beta (L x m),
/// prediction Y = H beta.

#include <Eigen/Core>
#include <cstdint>

namespace vid::massid::elm {

/// @brief The random hidden layer of Algorithm 1 (steps 1-2): input weights a_j and biases
/// b_j drawn once from U(-scale, scale) with a seeded generator (same seed -> bit-identical
/// layer), activation g(z) = 1 / (1 + exp(-z)).
class HiddenLayer {
 public:
  HiddenLayer() = default;
  /// @param inputs  input dimension d (> 0)
  /// @param hidden  number of hidden nodes L (> 0)
  /// @param seed    seed of the weight/bias generator
  /// @param scale   half-width of the uniform distribution of weights and biases
  /// @throws std::invalid_argument on non-positive sizes or scale
  HiddenLayer(int inputs, int hidden, std::uint64_t seed, double scale = 1.0);

  int inputs() const { return static_cast<int>(W_.cols()); }
  int hidden() const { return static_cast<int>(W_.rows()); }
  /// @brief Input weights (L x d), row j = a_j.
  const Eigen::MatrixXd& weights() const { return W_; }
  /// @brief Biases (L).
  const Eigen::VectorXd& biases() const { return b_; }

  /// @brief Hidden-layer output matrix H (Algorithm 1 step 2) of a batch X (N x d) -> N x L.
  /// @throws std::invalid_argument when X has the wrong number of columns
  Eigen::MatrixXd activations(const Eigen::MatrixXd& X) const;
  /// @brief Hidden-layer output h(x) (L) of one input x (d), the row of H for that sample.
  Eigen::VectorXd activation(const Eigen::VectorXd& x) const;

 private:
  Eigen::MatrixXd W_;
  Eigen::VectorXd b_;
};

/// @brief ELM output weights, Algorithm 1 step 3: beta = H^+ T, computed as the least-squares
/// solution by column-pivoting Householder QR of H (rank-revealing, so a rank-deficient H
/// still gives a finite minimum-residual solution; no explicit (pseudo-)inverse is formed).
/// @throws std::invalid_argument when H and T have different row counts or are empty
Eigen::MatrixXd solve_elm(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T);

/// @brief RELM output weights, docs/model.md eq. (60): beta = (H^T H + lambda I)^-1 H^T T, evaluated as
/// a Cholesky (LLT) solve of the symmetric positive-definite normal equations. The Gram
/// matrix is formed as a symmetric rank-N update (half the flops of a general product).
/// @param lambda  ridge weight (> 0)
/// @throws std::invalid_argument on bad sizes or lambda <= 0; std::runtime_error when the
///         Cholesky factorization fails (lambda too small for the round-off of H^T H)
Eigen::MatrixXd solve_relm(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T, double lambda);

/// @brief The regularized Gram matrix lambda I + H^T H (full symmetric, L x L); exposed for
/// OSELM's initial batch (eq. 30) and for tests.
Eigen::MatrixXd regularized_gram(const Eigen::MatrixXd& H, double lambda);

/// @brief Naive reference used only to measure the speed-up (benchmarks, `elm-study`):
/// beta = pinv(H) T with Eigen's CompleteOrthogonalDecomposition::pseudoInverse(), i.e. the
/// explicit Moore-Penrose pseudo-inverse (N x L formed in memory) as a straightforward
/// implementation of Algorithm 1 would do. Not used by the estimators.
Eigen::MatrixXd solve_elm_naive_pinv(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T);

/// @brief Naive RELM reference (benchmarks only): beta = (H^T H + lambda I)^-1 H^T T with an
/// explicit inverse of the Gram matrix (general product, FullPivLU inverse).
Eigen::MatrixXd solve_relm_naive_inverse(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T,
                                         double lambda);

}  // namespace vid::massid::elm
