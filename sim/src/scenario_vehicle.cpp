/// @file scenario_vehicle.cpp
/// @brief `vehicle:` and `controller:` sections of a scenario.

#include <stdexcept>

#include "scenario_parts.h"

namespace vid::sim::detail {

void parse_vehicle(const YamlSection& v, Scenario* s) {
  dynamics::QuadrotorParams& p = s->vehicle;
  p.mass_kg = v.num("mass_kg", 1.0);
  p.gravity = v.num("gravity", 9.81);
  const Eigen::Vector3d J = v.vec3("inertia_diag", Eigen::Vector3d(0.01, 0.01, 0.018));
  p.inertia = J.asDiagonal();
  p.arm_length_m = v.num("arm_length_m", 0.2);
  const std::string layout = v.str("layout", "x");
  std::vector<double> k = {1e-7, 1e-7, 1e-7, 1e-7};
  if (v.has("thrust_coefficients")) k = v.nums("thrust_coefficients");
  else v.raw("thrust_coefficients");
  std::vector<int> dirs;
  if (v.has("rotor_directions")) {
    for (double d : v.nums("rotor_directions")) dirs.push_back(static_cast<int>(d));
  } else {
    v.raw("rotor_directions");
  }
  const double torque_ratio = v.num("torque_to_thrust_m", 0.016);
  p.motor_time_constant_s = v.num("motor_time_constant_s", 0.03);
  s->rotor_unit = v.str("rotor_speed_unit", "rpm");
  p.rotor_speed_min = v.num("rotor_speed_min", 0.0);
  p.rotor_speed_max = v.num("rotor_speed_max", 1e5);
  p.linear_drag = v.vec3("linear_drag", Eigen::Vector3d::Zero());
  v.finish();
  if (s->rotor_unit != "rpm" && s->rotor_unit != "rad/s") v.fail("rotor_speed_unit", "expected rpm or rad/s");
  if (!(p.mass_kg > 0.0)) v.fail("mass_kg", "must be > 0");
  if (!(p.gravity > 0.0)) v.fail("gravity", "must be > 0");
  if (!(J.minCoeff() > 0.0)) v.fail("inertia_diag", "must be > 0");
  if (!(p.arm_length_m > 0.0)) v.fail("arm_length_m", "must be > 0");
  if (p.linear_drag.minCoeff() < 0.0) v.fail("linear_drag", "must be >= 0");
  try {
    p.rotors = dynamics::QuadrotorParams::symmetric_layout(layout, p.arm_length_m, k, dirs, torque_ratio);
    p.validate();
  } catch (const std::invalid_argument& e) {
    v.fail("thrust_coefficients", e.what());
  }
  // The vehicle must be able to hover with margin.
  double max_thrust = 0.0;
  for (const auto& r : p.rotors) max_thrust += r.thrust_coeff * p.rotor_speed_max * p.rotor_speed_max;
  if (max_thrust < 1.3 * p.mass_kg * p.gravity)
    v.fail("rotor_speed_max", "maximum thrust is below 1.3 x weight");
}

void parse_controller(const YamlSection& c, ControllerGains* g) {
  g->kp = c.vec3("kp", g->kp);
  g->kv = c.vec3("kv", g->kv);
  g->ki = c.vec3("ki", g->ki);
  g->kr = c.vec3("kr", g->kr);
  g->kw = c.vec3("kw", g->kw);
  g->integral_limit = c.num("integral_limit", g->integral_limit);
  g->disturbance_tau_s = c.num("disturbance_tau_s", g->disturbance_tau_s);
  c.finish();
}

}  // namespace vid::sim::detail
