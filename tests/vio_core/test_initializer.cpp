// The still/hover window test of the static initializer (vio_core/initializer.h): what it must
// accept (a resting or hovering IMU with its white noise and bias) and refuse (turning, moving).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "vio_core/initializer.h"

namespace {
using namespace vid;
using Eigen::Vector3d;

constexpr double kRate = 400.0;

// Feeds the initializer IMU samples from f(t) -> (gyro, accel) plus white noise at the
// params' densities, and returns the first result (or nullopt after duration_s).
template <class F>
std::optional<InitResult> feed(StaticInitializer& init, const EstimatorParams& p, double duration_s, F f,
                               unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  const double sg = p.gyro_noise_density * std::sqrt(kRate), sa = p.accel_noise_density * std::sqrt(kRate);
  for (int i = 0; i < static_cast<int>(duration_s * kRate); ++i) {
    const double t = i / kRate;
    auto [w, a] = f(t);
    for (int k = 0; k < 3; ++k) {
      w[k] += sg * n01(rng);
      a[k] += sa * n01(rng);
    }
    if (auto r = init.add(static_cast<TimeNs>(std::llround(t * 1e9)), w, a, Vector3d(0, 0, 9.81))) return r;
  }
  return std::nullopt;
}

EstimatorParams sim_params() {
  EstimatorParams p;  // the simulator presets' IMU and thresholds (config/sim/estimator.yaml)
  p.accel_noise_density = 0.1;
  p.gyro_noise_density = 1e-3;
  p.init_accel_std_max = 4.5;
  p.init_gyro_std_max = 0.06;
  return p;
}

TEST(StaticInit, StillWindowGivesGravityAndGyroBias) {
  const EstimatorParams p = sim_params();
  StaticInitializer init(p);
  const Vector3d b_g(0.004, -0.006, 0.008);
  const auto r = feed(init, p, 2.0, [&](double) { return std::pair{b_g, Vector3d(0.0, 0.0, 9.81)}; });
  ASSERT_TRUE(r.has_value()) << init.last_rejection();
  EXPECT_LE(r->t_ns, 510'000'000);  // the first full 0.5 s window
  EXPECT_LT((r->x.b_g - b_g).norm(), 2e-3);
  const Vector3d z_I = r->x.T_WI.q.conjugate() * Vector3d::UnitZ();
  EXPECT_GT(z_I.z(), std::cos(0.02));
}

TEST(StaticInit, ConstantYawIsTurningNotStill) {
  // fast_yaw: 3 rad/s about z, gravity constant in the body frame; the samples' spread is only
  // their noise, so only the mean rate shows the turn.
  const EstimatorParams p = sim_params();
  StaticInitializer init(p);
  const auto r = feed(init, p, 3.0, [](double) { return std::pair{Vector3d(0, 0, 3.0), Vector3d(0, 0, 9.81)}; });
  EXPECT_FALSE(r.has_value());
  EXPECT_NE(init.last_rejection().find("turning"), std::string::npos) << init.last_rejection();
}

TEST(StaticInit, SlowTurnBeyondTheBiasPriorIsRefused) {
  // 0.05 rad/s is 5 init_sigma_gyro_bias (0.01): taking it as bias would be a 5-sigma error.
  const EstimatorParams p = sim_params();
  StaticInitializer init(p);
  EXPECT_FALSE(feed(init, p, 3.0, [](double) { return std::pair{Vector3d(0.05, 0, 0), Vector3d(0, 0, 9.81)}; }));
  // ... while a bias inside the prior (0.02 rad/s, 2 sigma) is accepted.
  StaticInitializer init2(p);
  EXPECT_TRUE(feed(init2, p, 3.0, [](double) { return std::pair{Vector3d(0.02, 0, 0), Vector3d(0, 0, 9.81)}; }));
}

}  // namespace
