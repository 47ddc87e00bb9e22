/// @file oselm.cpp
/// @brief OSELM Woodbury recursion (seed Algorithm 2, eqs. 30-38).
#include "massid/elm/oselm.h"

#include <Eigen/Cholesky>
#include <stdexcept>
#include <string>

#include "massid/elm/elm.h"

namespace vid::massid::elm {

OnlineSequentialElm::OnlineSequentialElm(int hidden, int outputs, double lambda,
                                         double forgetting)
    : lambda_(lambda), mu_(forgetting) {
  if (hidden <= 0 || outputs <= 0) {
    throw std::invalid_argument("OnlineSequentialElm: hidden and outputs must be positive");
  }
  if (!(lambda > 0.0)) {
    throw std::invalid_argument("OnlineSequentialElm: lambda must be positive, got " +
                                std::to_string(lambda));
  }
  if (!(forgetting > 0.0 && forgetting <= 1.0)) {
    throw std::invalid_argument("OnlineSequentialElm: forgetting factor must be in (0, 1], got " +
                                std::to_string(forgetting));
  }
  // Ridge prior: P0 = I / lambda, beta0 = 0 (equivalent to no data under eq. 29).
  P_lower_ = Eigen::MatrixXd::Identity(hidden, hidden) / lambda;
  beta_ = Eigen::MatrixXd::Zero(hidden, outputs);
}

void OnlineSequentialElm::initialize(const Eigen::MatrixXd& H0, const Eigen::MatrixXd& T0) {
  if (samples_ != 0) {
    throw std::logic_error("OnlineSequentialElm::initialize: called after updates");
  }
  if (H0.rows() == 0 || H0.cols() != P_lower_.rows() || T0.rows() != H0.rows() ||
      T0.cols() != beta_.cols()) {
    throw std::invalid_argument("OnlineSequentialElm::initialize: batch sizes do not match "
                                "the network");
  }
  const Eigen::Index L = H0.cols();
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(regularized_gram(H0, lambda_));
  if (llt.info() != Eigen::Success) {
    throw std::runtime_error("OnlineSequentialElm::initialize: H0^T H0 + lambda I is not "
                             "numerically positive definite");
  }
  P_lower_ = llt.solve(Eigen::MatrixXd::Identity(L, L));  // eq. 31
  beta_ = llt.solve(H0.transpose() * T0);                 // eq. 32
  samples_ = H0.rows();
}

void OnlineSequentialElm::update(const Eigen::MatrixXd& H, const Eigen::MatrixXd& T) {
  if (H.rows() == 0 || H.cols() != P_lower_.rows() || T.rows() != H.rows() ||
      T.cols() != beta_.cols()) {
    throw std::invalid_argument("OnlineSequentialElm::update: chunk sizes do not match the "
                                "network");
  }
  const auto P = P_lower_.selfadjointView<Eigen::Lower>();
  const Eigen::MatrixXd PHt = P * H.transpose();  // L x n
  Eigen::MatrixXd S = H * PHt;                    // n x n
  S.diagonal().array() += mu_;
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(S);
  // M = P H^T L_S^-T, so that P H^T S^-1 H P = M M^T and K = P H^T S^-1 = M L_S^-1.
  const Eigen::MatrixXd M =
      llt.matrixL().solve(PHt.transpose()).transpose();  // L x n
  const Eigen::MatrixXd innovation = T - H * beta_;       // n x m
  beta_.noalias() += M * llt.matrixL().solve(innovation);
  P_lower_.selfadjointView<Eigen::Lower>().rankUpdate(M, -1.0);
  if (mu_ != 1.0) P_lower_.triangularView<Eigen::Lower>() *= 1.0 / mu_;
  samples_ += H.rows();
}

void OnlineSequentialElm::update_one(const Eigen::VectorXd& h, const Eigen::VectorXd& t) {
  if (h.size() != P_lower_.rows() || t.size() != beta_.cols()) {
    throw std::invalid_argument("OnlineSequentialElm::update_one: sizes do not match the "
                                "network");
  }
  const Eigen::VectorXd Ph = P_lower_.selfadjointView<Eigen::Lower>() * h;
  const double s = mu_ + h.dot(Ph);
  const Eigen::RowVectorXd innovation = t.transpose() - h.transpose() * beta_;
  beta_.noalias() += (Ph / s) * innovation;
  P_lower_.selfadjointView<Eigen::Lower>().rankUpdate(Ph, -1.0 / s);
  if (mu_ != 1.0) P_lower_.triangularView<Eigen::Lower>() *= 1.0 / mu_;
  ++samples_;
}

Eigen::MatrixXd OnlineSequentialElm::P() const {
  Eigen::MatrixXd full = P_lower_.selfadjointView<Eigen::Lower>();
  return full;
}

}  // namespace vid::massid::elm
