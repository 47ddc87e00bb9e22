#pragma once
/// @file thrust.h
/// @brief Collective thrust from rotor speeds: T = sum_i k_i n_i^2 [N], n in the rotor
/// sensor's own unit (coefficients are per that unit; no rpm <-> rad/s conversion here),
/// and the mass-normalized body thrust T_m = [0, 0, T/m] [m/s^2].

#include <Eigen/Core>

#include "types/calibration.h"
#include "types/measurements.h"

namespace vid {

/// @brief T = sum_i k_i n_i^2 [N]. Throws std::invalid_argument if the number of speeds and
/// coefficients differ or there are none.
double collective_thrust(const RotorSample& rotors, const VehicleParams& vehicle);

/// @brief T_m = [0, 0, T/m] in I [m/s^2]. Throws std::invalid_argument if mass <= 0.
Eigen::Vector3d mass_normalized_thrust(double thrust_N, double mass_kg);

/// @brief Standard deviation of T from per-rotor speed noise sigma_n (same unit as n):
/// dT/dn_i = 2 k_i n_i, independent rotors.
double collective_thrust_sigma(const RotorSample& rotors, const VehicleParams& vehicle,
                               double sigma_n);

}  // namespace vid
