// SO(3)/quaternion helpers: identities and numeric differentiation, incl. angles near 0 and pi.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "geometry/so3.h"

namespace {
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using namespace vid;

const std::vector<double> kAngles = {0.0,      1e-9, 1e-5, 1e-3, 0.3, 1.0, 2.5,
                                     M_PI - 1e-5, M_PI - 1e-9};

std::vector<Vector3d> test_vectors() {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Vector3d> out;
  for (double a : kAngles) {
    for (int k = 0; k < 4; ++k) {
      Vector3d axis(n(rng), n(rng), n(rng));
      if (k == 0) axis = Vector3d(0, 0, 1);
      out.push_back(a * axis.normalized());
    }
  }
  return out;
}

// Rodrigues in long double as an independent reference.
Matrix3d reference_exp(const Vector3d& phi) {
  const long double t = std::sqrt((long double)phi.squaredNorm());
  if (t == 0.0L) return Matrix3d::Identity();
  const Vector3d u = phi / (double)t;
  const Matrix3d U = so3::skew(u);
  return Matrix3d::Identity() + (double)std::sin(t) * U + (double)(1.0L - std::cos(t)) * U * U;
}

TEST(So3, SkewVeeAndCrossProduct) {
  const Vector3d a(0.3, -1.2, 2.0), b(-0.7, 0.4, 1.1);
  EXPECT_LT((so3::skew(a) * b - a.cross(b)).norm(), 1e-15);
  EXPECT_LT((so3::skew(a).transpose() + so3::skew(a)).norm(), 1e-15);
  EXPECT_LT((so3::vee(so3::skew(a)) - a).norm(), 1e-15);
}

TEST(So3, ExpMatchesReferenceAndIsOrthonormal) {
  for (const Vector3d& phi : test_vectors()) {
    const Matrix3d R = so3::exp(phi);
    EXPECT_LT((R - reference_exp(phi)).norm(), 1e-14) << phi.transpose();
    EXPECT_LT((R.transpose() * R - Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
    // quaternion exp gives the same rotation
    EXPECT_LT((so3::quat_exp(phi).toRotationMatrix() - R).norm(), 1e-14);
  }
}

TEST(So3, LogInvertsExpIncludingNearZeroAndPi) {
  for (const Vector3d& phi : test_vectors()) {
    const Vector3d back = so3::log(so3::exp(phi));
    EXPECT_LT((back - phi).norm(), 1e-12 * std::max(1.0, phi.norm())) << phi.transpose();
    const Vector3d back_q = so3::quat_log(so3::quat_exp(phi));
    EXPECT_LT((back_q - phi).norm(), 1e-13 * std::max(1.0, phi.norm())) << phi.transpose();
    // relative accuracy near zero: tiny angles are not flushed to zero
    if (phi.norm() > 0.0 && phi.norm() < 1e-4) {
      EXPECT_LT((back - phi).norm(), 1e-6 * phi.norm());
    }
  }
}

TEST(So3, LogAtExactlyPiHasAnglePi) {
  const Vector3d axis = Vector3d(1, 2, -0.5).normalized();
  const Matrix3d R = so3::exp(M_PI * axis);
  const Vector3d phi = so3::log(R);
  EXPECT_NEAR(phi.norm(), M_PI, 1e-12);
  // either sign of the axis is a correct answer at pi
  EXPECT_LT(std::min((phi - M_PI * axis).norm(), (phi + M_PI * axis).norm()), 1e-7);
  EXPECT_LT((so3::exp(phi) - R).norm(), 1e-12);
}

TEST(So3, QuatLogHandlesBothSigns) {
  const Quaterniond q = so3::quat_exp(Vector3d(0.1, -0.2, 0.3));
  Quaterniond qn(-q.w(), -q.x(), -q.y(), -q.z());
  EXPECT_LT((so3::quat_log(q) - so3::quat_log(qn)).norm(), 1e-15);
}

// d/dd Log(Exp(phi)^T Exp(phi + d)) at d = 0, central differences.
Matrix3d numeric_right_jacobian(const Vector3d& phi) {
  Matrix3d J;
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i) {
    const Vector3d e = Vector3d::Unit(i) * h;
    const Vector3d plus = so3::log(so3::exp(phi).transpose() * so3::exp(phi + e));
    const Vector3d minus = so3::log(so3::exp(phi).transpose() * so3::exp(phi - e));
    J.col(i) = (plus - minus) / (2 * h);
  }
  return J;
}

Matrix3d numeric_left_jacobian(const Vector3d& phi) {
  Matrix3d J;
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i) {
    const Vector3d e = Vector3d::Unit(i) * h;
    const Vector3d plus = so3::log(so3::exp(phi + e) * so3::exp(phi).transpose());
    const Vector3d minus = so3::log(so3::exp(phi - e) * so3::exp(phi).transpose());
    J.col(i) = (plus - minus) / (2 * h);
  }
  return J;
}

TEST(So3, JacobiansMatchNumericDifferentiation) {
  for (const Vector3d& phi : test_vectors()) {
    const Matrix3d Jr = so3::right_jacobian(phi);
    const Matrix3d Jl = so3::left_jacobian(phi);
    EXPECT_LT((Jr - numeric_right_jacobian(phi)).norm(), 1e-6 * Jr.norm()) << phi.transpose();
    EXPECT_LT((Jl - numeric_left_jacobian(phi)).norm(), 1e-6 * Jl.norm()) << phi.transpose();
  }
}

TEST(So3, JacobianIdentitiesAndInverses) {
  for (const Vector3d& phi : test_vectors()) {
    const Matrix3d Jr = so3::right_jacobian(phi);
    const Matrix3d Jl = so3::left_jacobian(phi);
    const Matrix3d I = Matrix3d::Identity();
    EXPECT_LT((Jr * so3::right_jacobian_inv(phi) - I).norm(), 1e-11) << phi.transpose();
    EXPECT_LT((Jl * so3::left_jacobian_inv(phi) - I).norm(), 1e-11) << phi.transpose();
    // Jl = R Jr, Jl(phi) = Jr(-phi), Jr phi = phi
    EXPECT_LT((Jl - so3::exp(phi) * Jr).norm(), 1e-13);
    EXPECT_LT((Jl - Jr.transpose()).norm(), 1e-13);
    EXPECT_LT((Jr * phi - phi).norm(), 1e-13);
  }
}

TEST(So3, InverseRightJacobianMatchesNumericLogDerivative) {
  // Log(Exp(phi) Exp(d)) ≈ phi + Jr^-1 d (away from the pi cut, where Log jumps)
  for (const Vector3d& phi : test_vectors()) {
    if (phi.norm() > 3.0) continue;
    Matrix3d J;
    const double h = 1e-6;
    for (int i = 0; i < 3; ++i) {
      const Vector3d e = Vector3d::Unit(i) * h;
      J.col(i) = (so3::log(so3::exp(phi) * so3::exp(e)) - so3::log(so3::exp(phi) * so3::exp(-e))) /
                 (2 * h);
    }
    const Matrix3d Ji = so3::right_jacobian_inv(phi);
    EXPECT_LT((Ji - J).norm(), 1e-6 * Ji.norm()) << phi.transpose();
  }
}

TEST(So3, BoxplusBoxminusRoundTripAndRightPerturbation) {
  const Quaterniond q0 = so3::quat_exp(Vector3d(0.4, -1.0, 2.2));
  for (const Vector3d& d : test_vectors()) {
    const Quaterniond q1 = so3::boxplus(q0, d);
    EXPECT_NEAR(q1.norm(), 1.0, 1e-15);
    // right perturbation: R1 = R0 Exp(d)
    EXPECT_LT((q1.toRotationMatrix() - q0.toRotationMatrix() * so3::exp(d)).norm(), 1e-13);
    EXPECT_LT((so3::boxminus(q1, q0) - d).norm(), 1e-12 * std::max(1.0, d.norm()))
        << d.transpose();
  }
}

TEST(So3, NormalizedHasCanonicalSign) {
  const Quaterniond q(-2.0, 0.2, 0.0, -0.4);
  const Quaterniond n = so3::normalized(q);
  EXPECT_NEAR(n.norm(), 1.0, 1e-15);
  EXPECT_GE(n.w(), 0.0);
  EXPECT_LT((n.toRotationMatrix() - q.normalized().toRotationMatrix()).norm(), 1e-15);
  Matrix3d R = so3::exp(Vector3d(0.3, 0.2, 0.1));
  R(0, 0) += 1e-6;
  const Matrix3d Ro = so3::orthonormalized(R);
  EXPECT_LT((Ro.transpose() * Ro - Matrix3d::Identity()).norm(), 1e-14);
}

// vee of a difference X - X^T (the attitude error of a geometric controller) is its axial vector.
TEST(So3, VeeOfAntisymmetricDifference) {
  const Matrix3d R_a = so3::exp(Vector3d(0.3, -0.2, 1.1)), R_b = so3::exp(Vector3d(-0.5, 0.4, 0.2));
  const Matrix3d M = R_a.transpose() * R_b - R_b.transpose() * R_a;
  EXPECT_EQ(so3::vee(M), Vector3d(M(2, 1), M(0, 2), M(1, 0)));
}

}  // namespace
