/// @file elm.cpp
/// @brief ELM hidden layer and output-weight solvers (seed Algorithm 1, eq. 29).
#include "massid/elm/elm.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <random>
#include <stdexcept>
#include <string>

namespace vid::massid::elm {
namespace {

/// Uniform double in [0, 1) from the top 53 bits; std::uniform_real_distribution is
/// implementation-defined, this is the same on every standard library.
double unit_uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

void check_rows(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T, const char* who) {
  if (H.rows() == 0 || H.cols() == 0 || T.cols() == 0 || H.rows() != T.rows()) {
    throw std::invalid_argument(std::string(who) + ": H is " + std::to_string(H.rows()) + "x" +
                                std::to_string(H.cols()) + ", T is " + std::to_string(T.rows()) +
                                "x" + std::to_string(T.cols()) +
                                " (need non-empty, equal row counts)");
  }
}

}  // namespace

HiddenLayer::HiddenLayer(int inputs, int hidden, std::uint64_t seed, double scale) {
  if (inputs <= 0 || hidden <= 0 || !(scale > 0.0)) {
    throw std::invalid_argument("HiddenLayer: inputs " + std::to_string(inputs) + ", hidden " +
                                std::to_string(hidden) + ", scale " + std::to_string(scale) +
                                " (all must be positive)");
  }
  std::mt19937_64 rng(seed);
  W_.resize(hidden, inputs);
  b_.resize(hidden);
  // Row by row so that the first L' nodes of a larger layer equal a smaller layer's nodes.
  for (int j = 0; j < hidden; ++j) {
    for (int i = 0; i < inputs; ++i) W_(j, i) = scale * (2.0 * unit_uniform(rng) - 1.0);
    b_(j) = scale * (2.0 * unit_uniform(rng) - 1.0);
  }
}

Eigen::MatrixXd HiddenLayer::activations(const Eigen::MatrixXd& X) const {
  if (X.cols() != W_.cols()) {
    throw std::invalid_argument("HiddenLayer::activations: input has " +
                                std::to_string(X.cols()) + " columns, layer expects " +
                                std::to_string(W_.cols()));
  }
  Eigen::MatrixXd Z = X * W_.transpose();
  Z.rowwise() += b_.transpose();
  // g(z) = 1 / (1 + exp(-z)), vectorized.
  return (1.0 + (-Z.array()).exp()).inverse().matrix();
}

Eigen::VectorXd HiddenLayer::activation(const Eigen::VectorXd& x) const {
  if (x.size() != W_.cols()) {
    throw std::invalid_argument("HiddenLayer::activation: input has " + std::to_string(x.size()) +
                                " entries, layer expects " + std::to_string(W_.cols()));
  }
  const Eigen::VectorXd z = W_ * x + b_;
  return (1.0 + (-z.array()).exp()).inverse().matrix();
}

Eigen::MatrixXd solve_elm(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T) {
  check_rows(H, T, "solve_elm");
  return H.colPivHouseholderQr().solve(T);
}

Eigen::MatrixXd regularized_gram(const Eigen::MatrixXd& H, double lambda) {
  const Eigen::Index L = H.cols();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(L, L);
  G.selfadjointView<Eigen::Lower>().rankUpdate(H.transpose());
  G.diagonal().array() += lambda;
  G.triangularView<Eigen::StrictlyUpper>() = G.transpose();
  return G;
}

Eigen::MatrixXd solve_relm(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T, double lambda) {
  check_rows(H, T, "solve_relm");
  if (!(lambda > 0.0)) {
    throw std::invalid_argument("solve_relm: lambda must be positive, got " +
                                std::to_string(lambda));
  }
  const Eigen::Index L = H.cols();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(L, L);
  G.selfadjointView<Eigen::Lower>().rankUpdate(H.transpose());
  G.diagonal().array() += lambda;
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(G);
  if (llt.info() != Eigen::Success) {
    throw std::runtime_error("solve_relm: H^T H + lambda I is not numerically positive "
                             "definite (lambda " + std::to_string(lambda) + " too small)");
  }
  return llt.solve(H.transpose() * T);
}

Eigen::MatrixXd solve_elm_naive_pinv(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T) {
  check_rows(H, T, "solve_elm_naive_pinv");
  const Eigen::MatrixXd H_pinv = H.completeOrthogonalDecomposition().pseudoInverse();
  return H_pinv * T;
}

Eigen::MatrixXd solve_relm_naive_inverse(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T,
                                         double lambda) {
  check_rows(H, T, "solve_relm_naive_inverse");
  Eigen::MatrixXd G = H.transpose() * H;
  G.diagonal().array() += lambda;
  const Eigen::MatrixXd G_inv = G.inverse();
  return G_inv * (H.transpose() * T);
}

}  // namespace vid::massid::elm
