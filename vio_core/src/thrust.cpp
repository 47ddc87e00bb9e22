/// @file thrust.cpp
/// @brief Rotor speed -> collective thrust (quadratic per-rotor model).
#include "vio_core/thrust.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace vid {
namespace {
void check_sizes(const RotorSample& rotors, const VehicleParams& vehicle) {
  if (rotors.speeds.empty() ||
      rotors.speeds.size() != vehicle.rotor_thrust_coefficients.size()) {
    throw std::invalid_argument("rotor sample at t=" + std::to_string(rotors.t_ns) + " has " +
                                std::to_string(rotors.speeds.size()) +
                                " speeds but vehicle has " +
                                std::to_string(vehicle.rotor_thrust_coefficients.size()) +
                                " rotor_thrust_coefficients");
  }
}
}  // namespace

double collective_thrust(const RotorSample& rotors, const VehicleParams& vehicle) {
  check_sizes(rotors, vehicle);
  double T = 0.0;
  for (std::size_t i = 0; i < rotors.speeds.size(); ++i) {
    T += vehicle.rotor_thrust_coefficients[i] * rotors.speeds[i] * rotors.speeds[i];
  }
  return T;
}

Eigen::Vector3d mass_normalized_thrust(double thrust_N, double mass_kg) {
  if (!(mass_kg > 0.0)) {
    throw std::invalid_argument("vehicle mass_kg must be > 0, got " + std::to_string(mass_kg));
  }
  return Eigen::Vector3d(0.0, 0.0, thrust_N / mass_kg);
}

double collective_thrust_sigma(const RotorSample& rotors, const VehicleParams& vehicle,
                               double sigma_n) {
  check_sizes(rotors, vehicle);
  double var = 0.0;
  for (std::size_t i = 0; i < rotors.speeds.size(); ++i) {
    const double d = 2.0 * vehicle.rotor_thrust_coefficients[i] * rotors.speeds[i];
    var += d * d * sigma_n * sigma_n;
  }
  return std::sqrt(var);
}

}  // namespace vid
