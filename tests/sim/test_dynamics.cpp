/// @file test_dynamics.cpp
/// @brief Quadrotor model: thrust/torque, allocation, hover equilibrium, RK4 order, motor lag.

#include <gtest/gtest.h>

#include <cmath>

#include "dynamics/quadrotor.h"

namespace vid::dynamics {
namespace {

QuadrotorParams vid_like() {
  QuadrotorParams p;
  p.mass_kg = 3.1015;
  p.inertia = Eigen::Vector3d(0.0347, 0.0458, 0.0977).asDiagonal();
  p.arm_length_m = 0.325;
  p.rotors = QuadrotorParams::symmetric_layout("x", 0.325, {2.6890e-7, 2.8190e-7, 2.7263e-7, 2.7741e-7},
                                               {1, -1, 1, -1}, 0.016);
  p.motor_time_constant_s = 0.03;
  p.rotor_speed_min = 1000;
  p.rotor_speed_max = 9000;
  return p;
}

class ConstEnv : public Environment {
 public:
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  double m = 3.1015;
  Eigen::Vector3d force_W(double, const QuadrotorState&) const override { return f; }
  double mass_kg(double) const override { return m; }
};

TEST(Quadrotor, ThrustIsSumOfKnSquared) {
  const QuadrotorModel model(vid_like());
  const Eigen::Vector4d n(5000, 5100, 5200, 5300);
  Eigen::Vector3d T, M;
  model.thrust_and_torque(n, &T, &M);
  double expected = 0.0;
  for (int i = 0; i < 4; ++i) expected += model.params().rotors[i].thrust_coeff * n[i] * n[i];
  EXPECT_NEAR(T.z(), expected, 1e-12 * expected);
  EXPECT_EQ(T.x(), 0.0);
  // Allocation matrix reproduces thrust and torque.
  const Eigen::Vector4d w = model.allocation_matrix() * n.cwiseProduct(n);
  EXPECT_NEAR(w[0], T.z(), 1e-9);
  EXPECT_NEAR((w.tail<3>() - M).norm(), 0.0, 1e-9);
}

TEST(Quadrotor, ReactionTorqueOpposesSpinDirection) {
  const QuadrotorModel model(vid_like());
  // Speed up the counter-clockwise rotors (0, 2): the body must be pushed clockwise (-z).
  Eigen::Vector3d T, M;
  model.thrust_and_torque(Eigen::Vector4d(6000, 5000, 6000, 5000), &T, &M);
  EXPECT_LT(M.z(), 0.0);
}

TEST(Quadrotor, HoverIsAnEquilibrium) {
  const QuadrotorModel model(vid_like());
  ConstEnv env;
  const Eigen::MatrixXd A = model.allocation_matrix();
  const Eigen::Vector4d wrench(env.m * 9.81, 0, 0, 0);
  const Eigen::VectorXd u = A.fullPivLu().solve(wrench);
  QuadrotorState x;
  x.rotor_speeds = u.cwiseSqrt();
  const Eigen::VectorXd cmd = x.rotor_speeds;
  for (int i = 0; i < 2000; ++i) x = model.rk4_step(i * 1e-3, 1e-3, x, cmd, env);
  EXPECT_LT(x.p_WI.norm(), 1e-9);
  EXPECT_LT(x.w_I.norm(), 1e-9);
}

TEST(Quadrotor, MotorLagIsFirstOrder) {
  const QuadrotorModel model(vid_like());
  ConstEnv env;
  QuadrotorState x;
  x.rotor_speeds = Eigen::Vector4d::Constant(4000);
  const Eigen::VectorXd cmd = Eigen::Vector4d::Constant(6000);
  const double tau = model.params().motor_time_constant_s;
  for (int i = 0; i < 30; ++i) x = model.rk4_step(i * 1e-3, 1e-3, x, cmd, env);
  const double expected = 6000 - 2000 * std::exp(-0.030 / tau);
  EXPECT_NEAR(x.rotor_speeds[0], expected, 1e-6 * expected);
  // Commands are clamped to the speed limits.
  const Eigen::VectorXd high = Eigen::Vector4d::Constant(20000);
  for (int i = 0; i < 1000; ++i) x = model.rk4_step(i * 1e-3, 1e-3, x, high, env);
  EXPECT_NEAR(x.rotor_speeds.maxCoeff(), 9000.0, 1e-3);
}

TEST(Quadrotor, Rk4IsFourthOrder) {
  // Spinning, tilted vehicle under a side force: halving the step must cut the error ~16x.
  const QuadrotorModel model(vid_like());
  ConstEnv env;
  env.f = Eigen::Vector3d(3.0, -2.0, 1.0);
  QuadrotorState x0;
  x0.q_WI = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()));
  x0.w_I = Eigen::Vector3d(1.0, -0.5, 2.0);
  x0.v_WI = Eigen::Vector3d(0.5, 0.2, -0.1);
  x0.rotor_speeds = Eigen::Vector4d(5000, 5600, 5200, 5400);
  const Eigen::VectorXd cmd = Eigen::Vector4d(6000, 5000, 5800, 5100);
  auto run = [&](int steps) {
    QuadrotorState x = x0;
    const double h = 0.5 / steps;
    for (int i = 0; i < steps; ++i) x = model.rk4_step(i * h, h, x, cmd, env);
    return x;
  };
  const QuadrotorState ref = run(4000);
  const double e1 = (run(50).p_WI - ref.p_WI).norm();
  const double e2 = (run(100).p_WI - ref.p_WI).norm();
  EXPECT_GT(e1 / e2, 12.0);
  EXPECT_LT(e1 / e2, 20.0);
}

TEST(Quadrotor, LinearDragOpposesBodyVelocity) {
  QuadrotorParams p = vid_like();
  p.linear_drag = Eigen::Vector3d(0.3, 0.3, 0.1);
  const QuadrotorModel model(p);
  ConstEnv env;
  QuadrotorState x;
  x.v_WI = Eigen::Vector3d(2.0, 0.0, 0.0);
  x.rotor_speeds = Eigen::Vector4d::Constant(5000);
  const ForceBreakdown f = model.forces(0.0, x, env);
  EXPECT_NEAR(f.drag_W.x(), -0.6, 1e-12);
  EXPECT_NEAR(f.external_W().x(), -0.6, 1e-12);
}

TEST(Quadrotor, RejectsBadParameters) {
  QuadrotorParams p = vid_like();
  p.mass_kg = -1.0;
  EXPECT_THROW(QuadrotorModel{p}, std::invalid_argument);
  EXPECT_THROW(QuadrotorParams::symmetric_layout("h", 0.2, {1, 1, 1, 1}, {}, 0.01), std::invalid_argument);
}

}  // namespace
}  // namespace vid::dynamics
