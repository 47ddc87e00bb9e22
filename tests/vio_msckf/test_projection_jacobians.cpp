/// Analytic Jacobians of the MSCKF camera model (clone pose, extrinsics, feature) and of the
/// inverse-depth triangulation residual against central differences.

#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "geometry/so3.h"
#include "vio_core/msckf/projection.h"
#include "vio_core/msckf/triangulation.h"

namespace vid::msckf {
namespace {

/// Central-difference Jacobian of f: R^k -> R^2 at 0.
template <int K>
Eigen::Matrix<double, 2, K> numeric_jacobian(
    const std::function<Eigen::Vector2d(const Eigen::Matrix<double, K, 1>&)>& f,
    double h = 1e-6) {
  Eigen::Matrix<double, 2, K> J;
  for (int k = 0; k < K; ++k) {
    Eigen::Matrix<double, K, 1> d = Eigen::Matrix<double, K, 1>::Zero();
    d(k) = h;
    J.col(k) = (f(d) - f(-d)) / (2.0 * h);
  }
  return J;
}

template <typename A, typename B>
double rel_error(const A& analytic, const B& numeric) {
  return (analytic - numeric).norm() / std::max(analytic.norm(), 1e-12);
}

struct Config {
  Eigen::Matrix3d R_WI;
  Eigen::Vector3d p_WI;
  Eigen::Isometry3d T_IC;
  Eigen::Vector3d p_W;
};

Config random_config(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Config c;
  c.R_WI = so3::exp(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1.5);
  c.p_WI = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 3.0;
  c.T_IC = Eigen::Isometry3d::Identity();
  c.T_IC.linear() = so3::exp(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0);
  c.T_IC.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.2;
  // Point 2..6 m in front of the camera, inside a 90 deg cone.
  const Eigen::Vector3d p_C(u(rng), u(rng), 4.0 + 2.0 * u(rng));
  const Eigen::Vector3d p_I = c.T_IC * p_C;
  c.p_W = c.R_WI * p_I + c.p_WI;
  return c;
}

TEST(ProjectionJacobians, MatchNumericDifferentiation) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Config c = random_config(rng);
    ProjectionJacobians J;
    ASSERT_TRUE(project_with_jacobians(c.R_WI, c.p_WI, c.T_IC, c.p_W, &J));
    Eigen::Vector2d z_plain;
    ASSERT_TRUE(project_point(c.R_WI, c.p_WI, c.T_IC, c.p_W, &z_plain));
    EXPECT_LT((z_plain - J.z).norm(), 1e-15);
    EXPECT_LT((J.z - J.p_C.head<2>() / J.p_C.z()).norm(), 1e-15);

    auto proj = [](const Eigen::Matrix3d& R, const Eigen::Vector3d& p, const Eigen::Isometry3d& T,
                   const Eigen::Vector3d& pw) {
      Eigen::Vector2d z;
      EXPECT_TRUE(project_point(R, p, T, pw, &z));
      return z;
    };
    const auto num_clone = numeric_jacobian<6>([&](const Eigen::Matrix<double, 6, 1>& d) {
      return proj(c.R_WI * so3::exp(d.head<3>()), c.p_WI + d.tail<3>(), c.T_IC, c.p_W);
    });
    const auto num_ext = numeric_jacobian<6>([&](const Eigen::Matrix<double, 6, 1>& d) {
      Eigen::Isometry3d T = c.T_IC;
      T.linear() = c.T_IC.linear() * so3::exp(d.head<3>());
      T.translation() += d.tail<3>();
      return proj(c.R_WI, c.p_WI, T, c.p_W);
    });
    const auto num_feat = numeric_jacobian<3>([&](const Eigen::Vector3d& d) {
      return proj(c.R_WI, c.p_WI, c.T_IC, c.p_W + d);
    });
    EXPECT_LT(rel_error(J.H_clone, num_clone), 1e-6) << "trial " << trial;
    EXPECT_LT(rel_error(J.H_extrinsic, num_ext), 1e-6) << "trial " << trial;
    EXPECT_LT(rel_error(J.H_feature, num_feat), 1e-6) << "trial " << trial;
    // Each block separately too, so a small wrong block is not hidden by a large right one.
    EXPECT_LT(rel_error(J.H_clone.leftCols<3>(), num_clone.leftCols<3>()), 1e-6);
    EXPECT_LT(rel_error(J.H_clone.rightCols<3>(), num_clone.rightCols<3>()), 1e-6);
    EXPECT_LT(rel_error(J.H_extrinsic.leftCols<3>(), num_ext.leftCols<3>()), 1e-6);
    EXPECT_LT(rel_error(J.H_extrinsic.rightCols<3>(), num_ext.rightCols<3>()), 1e-6);
  }
}

TEST(ProjectionJacobians, RejectsPointsBehindCamera) {
  const Eigen::Isometry3d T_IC = Eigen::Isometry3d::Identity();
  ProjectionJacobians J;
  Eigen::Vector2d z;
  EXPECT_FALSE(project_with_jacobians(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), T_IC,
                                      Eigen::Vector3d(0.1, 0.2, -3.0), &J));
  EXPECT_FALSE(project_point(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), T_IC,
                             Eigen::Vector3d(0.1, 0.2, 0.0), &z));
  EXPECT_TRUE(project_point(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), T_IC,
                            Eigen::Vector3d(0.1, 0.2, 2.0), &z));
  EXPECT_NEAR(z.x(), 0.05, 1e-15);
  EXPECT_NEAR(z.y(), 0.1, 1e-15);
}

TEST(InverseDepthJacobian, MatchesNumericDifferentiation) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix3d R_CA = so3::exp(Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.3);
    const Eigen::Vector3d p_CA = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.5;
    const Eigen::Vector3d abr(0.3 * u(rng), 0.3 * u(rng), 0.2 + 0.1 * u(rng));
    Eigen::Vector2d z;
    Eigen::Matrix<double, 2, 3> J;
    ASSERT_TRUE(inverse_depth_projection(abr, R_CA, p_CA, &z, &J));
    // Prediction equals the plain projection of p_C = R_CA p_A + p_CA.
    const Eigen::Vector3d p_C = R_CA * (Eigen::Vector3d(abr.x(), abr.y(), 1.0) / abr.z()) + p_CA;
    EXPECT_LT((z - p_C.head<2>() / p_C.z()).norm(), 1e-12);
    const auto num = numeric_jacobian<3>([&](const Eigen::Vector3d& d) {
      Eigen::Vector2d zz;
      EXPECT_TRUE(inverse_depth_projection(abr + d, R_CA, p_CA, &zz, nullptr));
      return zz;
    });
    EXPECT_LT(rel_error(J, num), 1e-6) << "trial " << trial;
  }
}

}  // namespace
}  // namespace vid::msckf
