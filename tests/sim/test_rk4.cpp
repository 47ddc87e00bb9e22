/// @file test_rk4.cpp
/// @brief The one RK4 step (dynamics/rk4.h): exact on a cubic, the 4th-order Taylor factor on
/// an exponential, 4th-order convergence, and a state that is a struct of Eigen vectors.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>

#include "dynamics/rk4.h"

namespace vid::dynamics {
namespace {

double add_scaled(double x, double d, double s) { return x + s * d; }

/// Integrate x' = f(t, x) from 0 to t_end in n steps.
template <class F>
double integrate(F f, double x0, double t_end, int n) {
  double x = x0;
  const double h = t_end / n;
  for (int i = 0; i < n; ++i) x = rk4_step<double>(i * h, h, x, f, add_scaled);
  return x;
}

TEST(Rk4, ExactWhenTheDerivativeIsACubicInTime) {
  // x' = 4 t^3 - 3 t^2 + 2: RK4 is Simpson's rule here, exact for a cubic integrand.
  auto f = [](double t, double) { return 4 * t * t * t - 3 * t * t + 2; };
  auto exact = [](double t) { return t * t * t * t - t * t * t + 2 * t + 1; };
  EXPECT_NEAR(integrate(f, exact(0.0), 2.0, 1), exact(2.0), 1e-12);
  EXPECT_NEAR(integrate(f, exact(0.0), 2.0, 7), exact(2.0), 1e-12);
}

TEST(Rk4, OneStepIsTheTaylorPolynomialOfTheExponential) {
  // x' = l x: one step multiplies by 1 + z + z^2/2 + z^3/6 + z^4/24 with z = l h.
  const double l = -1.7, h = 0.3, z = l * h;
  auto f = [l](double, double x) { return l * x; };
  EXPECT_NEAR(rk4_step<double>(0.0, h, 2.0, f, add_scaled), 2.0 * (1 + z + z * z / 2 + z * z * z / 6 + z * z * z * z / 24),
              1e-15);
}

TEST(Rk4, FourthOrderOnAnExponential) {
  // x' = 1.3 x on [0, 2]: global error O(h^4), halving the step cuts it ~16x.
  auto f = [](double, double x) { return 1.3 * x; };
  const double exact = std::exp(2.6);
  const double e1 = std::abs(integrate(f, 1.0, 2.0, 40) - exact);
  const double e2 = std::abs(integrate(f, 1.0, 2.0, 80) - exact);
  EXPECT_GT(e1 / e2, 15.0);
  EXPECT_LT(e1 / e2, 16.5);
}

/// A state made of Eigen members, as the models use (position and velocity).
struct PV {
  Eigen::Vector3d p, v;
};
PV operator+(const PV& a, const PV& b) { return {a.p + b.p, a.v + b.v}; }
PV operator*(double s, const PV& d) { return {s * d.p, s * d.v}; }

TEST(Rk4, StructStateUnderConstantAcceleration) {
  // p' = v, v' = a: p is quadratic in t, which RK4 integrates exactly.
  const Eigen::Vector3d a(0.5, -1.0, -9.81);
  auto f = [&](double, const PV& x) { return PV{x.v, a}; };
  auto add = [](const PV& x, const PV& d, double s) { return x + s * d; };
  PV x{Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(-1, 0, 4)};
  const PV x0 = x;
  for (int i = 0; i < 10; ++i) x = rk4_step<PV>(0.1 * i, 0.1, x, f, add);
  EXPECT_LT((x.p - (x0.p + x0.v + 0.5 * a)).norm(), 1e-12);
  EXPECT_LT((x.v - (x0.v + a)).norm(), 1e-12);
}

}  // namespace
}  // namespace vid::dynamics
