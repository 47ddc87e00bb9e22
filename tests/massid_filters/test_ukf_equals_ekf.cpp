/// @file test_ukf_equals_ekf.cpp
/// @brief On a linear-Gaussian system the unscented transform is exact, so the UKF (eqs.
/// 15-17) must reproduce the EKF (eqs. 3-8) mean and covariance; both are the generic
/// ManifoldSystem templates used for the quadrotor.
#include <gtest/gtest.h>

#include <random>

#include "massid/filters/ekf.h"
#include "massid/filters/ukf.h"

namespace vid::massid {
namespace {

/// x' = A(dt) x + B u (constant-acceleration in 2-D plus a bias), y = C x.
struct LinearModel {
  static constexpr int kStateDim = 5;
  static constexpr int kMeasDim = 3;
  using State = Eigen::Matrix<double, 5, 1>;
  using Input = Eigen::Matrix<double, 2, 1>;
  using Meas = Eigen::Matrix<double, 3, 1>;
  Eigen::Matrix<double, 5, 5> A(double dt) const {
    Eigen::Matrix<double, 5, 5> a = Eigen::Matrix<double, 5, 5>::Identity();
    a(0, 2) = dt;
    a(1, 3) = dt;
    a(2, 4) = 0.3 * dt;  // bias leaks into the first velocity
    return a;
  }
  Eigen::Matrix<double, 5, 2> B(double dt) const {
    Eigen::Matrix<double, 5, 2> b = Eigen::Matrix<double, 5, 2>::Zero();
    b(2, 0) = dt;
    b(3, 1) = dt;
    return b;
  }
  Eigen::Matrix<double, 3, 5> C() const {
    Eigen::Matrix<double, 3, 5> c = Eigen::Matrix<double, 3, 5>::Zero();
    c(0, 0) = 1.0;
    c(1, 1) = 1.0;
    c(2, 2) = 0.5;
    c(2, 3) = 0.5;
    return c;
  }
  State propagate(const State& x, const Input& u, double dt) const { return A(dt) * x + B(dt) * u; }
  Eigen::Matrix<double, 5, 5> state_jacobian(const State&, const Input&, double dt) const { return A(dt); }
  Meas measure(const State& x) const { return C() * x; }
  Eigen::Matrix<double, 3, 5> measurement_jacobian(const State&) const { return C(); }
  static State boxplus(const State& x, const Eigen::Matrix<double, 5, 1>& d) { return x + d; }
  static Eigen::Matrix<double, 5, 1> boxminus(const State& a, const State& b) { return a - b; }
  static Eigen::Matrix<double, 3, 1> meas_boxminus(const Meas& a, const Meas& b) { return a - b; }
};
static_assert(ManifoldSystem<LinearModel>);

TEST(UkfVsEkf, IdenticalOnLinearProblem) {
  for (double kappa : {0.0, 1.0}) {
    ManifoldEkf<LinearModel> ekf;
    ManifoldUkf<LinearModel> ukf(LinearModel{}, UkfParams{1.0, 2.0, kappa, 1});
    LinearModel::State x0;
    x0 << 1.0, -2.0, 0.5, 0.1, 0.3;
    Eigen::Matrix<double, 5, 5> P0 = Eigen::Matrix<double, 5, 5>::Identity();
    P0(0, 2) = P0(2, 0) = 0.3;
    ekf.init(x0, P0);
    ukf.init(x0, P0);
    const Eigen::Matrix<double, 5, 5> Q = Eigen::Matrix<double, 5, 1>(1e-3, 1e-3, 1e-2, 1e-2, 1e-4).asDiagonal();
    const Eigen::Matrix<double, 3, 3> R = Eigen::Vector3d(0.04, 0.09, 0.01).asDiagonal();
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n01;
    for (int k = 0; k < 50; ++k) {
      const LinearModel::Input u(n01(rng), n01(rng));
      ekf.predict(u, 0.05, Q);
      ASSERT_TRUE(ukf.predict(u, 0.05, Q));
      EXPECT_LT((ekf.state() - ukf.state()).norm(), 1e-10) << k;
      EXPECT_LT((ekf.covariance() - ukf.covariance()).norm(), 1e-10) << k;
      const LinearModel::Meas y(n01(rng), n01(rng), n01(rng));
      ASSERT_TRUE(ekf.update(y, R));
      ASSERT_TRUE(ukf.update(y, R));
      EXPECT_LT((ekf.state() - ukf.state()).norm(), 1e-10) << k;
      EXPECT_LT((ekf.covariance() - ukf.covariance()).norm(), 1e-10) << k;
    }
    // The filters did move: the state is far from its start.
    EXPECT_GT((ekf.state() - x0).norm(), 0.5);
  }
}

}  // namespace
}  // namespace vid::massid
