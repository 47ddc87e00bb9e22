#pragma once
/// @file oselm.h
/// @brief Online sequential ELM (seed Algorithm 2, eqs. 30-38): the RELM solution updated
/// chunk by chunk with the Woodbury identity, optionally with exponential forgetting.
///
/// Initialization phase (eqs. 30-32): from an initial batch (H0, T0)
///   P0 = (H0^T H0 + lambda I)^-1,  beta0 = P0 H0^T T0,
/// or, with no initial batch, the pure ridge prior P0 = I / lambda, beta0 = 0.
/// Sequential phase (eqs. 33-38), chunk k+1 with hidden output H (n x L) and targets T:
///   S = mu I_n + H P_k H^T                      (n x n, SPD because P_k is)
///   P_{k+1} = (P_k - P_k H^T S^-1 H P_k) / mu   (Woodbury form of (mu P_k^-1 + H^T H)^-1)
///   beta_{k+1} = beta_k + P_k H^T S^-1 (T - H beta_k)
/// With mu = 1 (no forgetting) this is exact recursive least squares: after every chunk,
/// beta equals the batch RELM solution (eq. 29) on all data seen so far.
/// With a forgetting factor mu in (0, 1) the cost being minimised is
///   sum_i mu^(n - i) |t_i - h_i beta|^2 + mu^n lambda |beta|^2,
/// i.e. old samples *and the ridge prior* fade geometrically (time constant 1 / (1 - mu)
/// samples); P may then grow in directions the recent data do not excite, so mu should stay
/// close to 1 (e.g. >= 0.999 at 100 Hz) for a 500-node network.
///
/// Only S (n x n, well conditioned: S >= mu I) is factorized (Cholesky); P is stored as its
/// lower triangle and updated by a symmetric rank-n downdate, so it stays exactly symmetric.
/// P0 from an initial batch needs (H0^T H0 + lambda I)^-1: it is obtained from the Cholesky
/// factor of that SPD matrix (the Woodbury recursion needs P itself).

#include <Eigen/Core>

namespace vid::massid::elm {

/// @brief Recursive (Woodbury) solver for the output weights of an OSELM.
class OnlineSequentialElm {
 public:
  /// @param hidden      L, number of hidden nodes
  /// @param outputs     m, number of targets
  /// @param lambda      ridge weight (> 0)
  /// @param forgetting  mu in (0, 1], 1 = no forgetting
  /// @throws std::invalid_argument on bad parameters
  OnlineSequentialElm(int hidden, int outputs, double lambda, double forgetting = 1.0);

  /// @brief Initialization phase from an initial batch (eqs. 30-32). May be skipped: the
  /// solver then starts from the ridge prior P0 = I / lambda, beta0 = 0.
  /// @throws std::invalid_argument on size mismatch, std::logic_error after an update,
  ///         std::runtime_error if H0^T H0 + lambda I is not numerically positive definite
  void initialize(const Eigen::MatrixXd& H0, const Eigen::MatrixXd& T0);

  /// @brief Sequential phase, one chunk (any number n >= 1 of rows; chunks may vary in size):
  /// eqs. 33-38 as in the file comment.
  /// @throws std::invalid_argument on size mismatch
  void update(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T);

  /// @brief Rank-one fast path of update() for one sample (h: L, t: m).
  void update_one(const Eigen::VectorXd& h, const Eigen::VectorXd& t);

  /// @brief Current output weights beta_k (L x m).
  const Eigen::MatrixXd& beta() const { return beta_; }
  /// @brief Current P_k as a full symmetric matrix (L x L).
  Eigen::MatrixXd P() const;
  /// @brief Number of samples absorbed so far (initial batch included).
  long samples() const { return samples_; }
  double lambda() const { return lambda_; }
  double forgetting() const { return mu_; }

 private:
  double lambda_;
  double mu_;
  Eigen::MatrixXd P_lower_;  ///< P_k, only the lower triangle is meaningful
  Eigen::MatrixXd beta_;
  long samples_ = 0;
};

}  // namespace vid::massid::elm
