// Thrust model and estimator parameter helpers.
#include <gtest/gtest.h>

#include <stdexcept>

#include "vio_core/estimator_params.h"
#include "vio_core/thrust.h"

namespace {
using namespace vid;

TEST(Thrust, CollectiveThrustIsSumOfQuadraticRotorThrusts) {
  VehicleParams v;
  v.mass_kg = 3.1015;
  v.rotor_thrust_coefficients = {2.6890e-7, 2.8190e-7, 2.7263e-7, 2.7741e-7};
  RotorSample r;
  r.speeds = {3000.0, 3100.0, 2900.0, 3050.0};
  const double expected = 2.6890e-7 * 9e6 + 2.8190e-7 * 3100.0 * 3100.0 +
                          2.7263e-7 * 2900.0 * 2900.0 + 2.7741e-7 * 3050.0 * 3050.0;
  EXPECT_NEAR(collective_thrust(r, v), expected, 1e-12);
  const Eigen::Vector3d Tm = mass_normalized_thrust(expected, v.mass_kg);
  EXPECT_DOUBLE_EQ(Tm.x(), 0.0);
  EXPECT_DOUBLE_EQ(Tm.y(), 0.0);
  EXPECT_NEAR(Tm.z(), expected / 3.1015, 1e-12);
  // sigma: numeric check of dT/dn for one rotor
  const double s = collective_thrust_sigma(r, v, 1.0);
  double var = 0;
  for (int i = 0; i < 4; ++i) {
    RotorSample rp = r;
    rp.speeds[i] += 1e-3;
    RotorSample rm = r;
    rm.speeds[i] -= 1e-3;
    const double d = (collective_thrust(rp, v) - collective_thrust(rm, v)) / 2e-3;
    var += d * d;
  }
  EXPECT_NEAR(s, std::sqrt(var), 1e-9);
}

TEST(Thrust, BadInputThrows) {
  VehicleParams v;
  v.rotor_thrust_coefficients = {1e-7, 1e-7};
  RotorSample r;
  r.speeds = {1.0, 2.0, 3.0};
  EXPECT_THROW(collective_thrust(r, v), std::invalid_argument);
  EXPECT_THROW(mass_normalized_thrust(1.0, 0.0), std::invalid_argument);
}

TEST(EstimatorParams, EnumsRoundTripAndRejectUnknown) {
  for (auto m : {PropagationMode::kImu, PropagationMode::kDynamics}) {
    EXPECT_EQ(mode_from_string(to_string(m)), m);
  }
  for (auto m : {InitMode::kStatic, InitMode::kGroundTruth}) {
    EXPECT_EQ(init_mode_from_string(to_string(m)), m);
  }
  EXPECT_THROW(mode_from_string("vio"), std::invalid_argument);
  EXPECT_THROW(init_mode_from_string(""), std::invalid_argument);
  EstimatorParams p;
  EXPECT_EQ(p.window_size, 11);
  EXPECT_EQ(p.mode, PropagationMode::kDynamics);
}

}  // namespace
