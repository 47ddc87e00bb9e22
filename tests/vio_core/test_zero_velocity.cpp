// Zero-velocity update of a parallax-free window (vio_core/zero_velocity.h): the parallax
// statistic against projective geometry, and the update against the textbook formula.
#include <gtest/gtest.h>

#include <random>

#include "geometry/so3.h"
#include "vio_core/zero_velocity.h"

namespace {
using namespace vid;
using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

// Points in front of camera "old"; returns (uv_old, uv_new) for the camera moved by (R, t):
// x_new = R_new_old x_old + t_new_old.
std::vector<std::pair<Vector2d, Vector2d>> observe(const Matrix3d& R_new_old, const Vector3d& t_new_old,
                                                   double depth_min, double depth_max, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5), d(depth_min, depth_max);
  std::vector<std::pair<Vector2d, Vector2d>> out;
  for (int i = 0; i < n; ++i) {
    const Vector3d x_old = d(rng) * Vector3d(u(rng), u(rng), 1.0);
    const Vector3d x_new = R_new_old * x_old + t_new_old;
    out.emplace_back(x_old.head<2>() / x_old.z(), x_new.head<2>() / x_new.z());
  }
  return out;
}

TEST(ZeroVelocity, PureRotationHasNoParallax) {
  const Matrix3d R = so3::exp(Vector3d(0.05, -0.2, 0.1));
  const WindowParallax px = rotation_compensated_parallax(observe(R, Vector3d::Zero(), 1.0, 20.0, 50, 1), R, 450.0);
  EXPECT_EQ(px.features, 50);
  EXPECT_LT(px.median_px, 1e-9);
  // Without the rotation removed, the same pairs move by tens of pixels.
  EXPECT_GT(rotation_compensated_parallax(observe(R, Vector3d::Zero(), 1.0, 20.0, 50, 1), Matrix3d::Identity(), 450.0)
                .median_px,
            10.0);
}

TEST(ZeroVelocity, TranslationShowsAsParallaxOverDepth) {
  // 5 mm sideways at 3 m: f * 0.005 / 3 = 0.75 px for every point at that depth.
  const Matrix3d R = so3::exp(Vector3d(0.0, 0.1, 0.0));
  const WindowParallax px = rotation_compensated_parallax(observe(R, Vector3d(0.005, 0, 0), 3.0, 3.0, 40, 2), R, 450.0);
  EXPECT_NEAR(px.median_px, 0.75, 0.02);
  // A point rotated behind the camera has no prediction and is not counted.
  const Matrix3d half_turn = so3::exp(Vector3d(0.0, M_PI, 0.0));
  auto pairs = observe(Matrix3d::Identity(), Vector3d::Zero(), 2.0, 4.0, 5, 3);
  EXPECT_EQ(rotation_compensated_parallax(pairs, half_turn, 450.0).features, 0);
  EXPECT_EQ(rotation_compensated_parallax({}, R, 450.0).features, 0);
}

TEST(ZeroVelocity, UpdateIsTheKalmanUpdateOfVelocity) {
  FilterState s(false, ForceFrame::kBody, false);
  ImuState x;
  x.v_WI = Vector3d(0.3, -0.2, 0.1);
  std::mt19937 rng(4);
  std::normal_distribution<double> nd(0, 1);
  Eigen::MatrixXd A(s.imu_dim(), s.imu_dim());
  for (int i = 0; i < A.rows(); ++i)
    for (int j = 0; j < A.cols(); ++j) A(i, j) = nd(rng);
  const Eigen::MatrixXd P0 = 0.05 * A * A.transpose() / A.rows() + 0.01 * Eigen::MatrixXd::Identity(A.rows(), A.rows());
  s.initialize(0, x, P0);
  const double sigma = 0.02;
  // Textbook: K = P H^T (H P H^T + R)^-1 with H selecting v.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, s.dim());
  H.block<3, 3>(0, imu_idx::kV).setIdentity();
  const Eigen::MatrixXd S = H * P0 * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(3, 3);
  const Eigen::MatrixXd K = P0 * H.transpose() * S.inverse();
  const Eigen::VectorXd dx = K * (-x.v_WI);
  const Eigen::MatrixXd P1 = P0 - K * S * K.transpose();
  ASSERT_TRUE(zero_velocity_update(s, sigma));
  EXPECT_LT((s.imu().v_WI - (x.v_WI + dx.segment<3>(imu_idx::kV))).norm(), 1e-12);
  EXPECT_LT((s.imu().T_WI.p - dx.segment<3>(imu_idx::kP)).norm(), 1e-12);
  EXPECT_LT((s.P() - P1).norm(), 1e-12);
  EXPECT_LT(s.imu().v_WI.norm(), 0.05 * x.v_WI.norm());  // sigma << prior sigma: v goes to ~0
}

}  // namespace
