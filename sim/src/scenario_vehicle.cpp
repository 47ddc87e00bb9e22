/// @file scenario_vehicle.cpp
/// @brief `vehicle:` and `controller:` sections of a scenario.

#include <stdexcept>

#include "scenario_parts.h"

namespace vid::sim::detail {

void parse_vehicle(const io::YamlMap& v, Scenario* s) {
  dynamics::QuadrotorParams& p = s->vehicle;
  p.mass_kg = v.get_double("mass_kg", 1.0);
  p.gravity = v.get_double("gravity", 9.81);
  const Eigen::Vector3d J = v.get_vec3("inertia_diag", Eigen::Vector3d(0.01, 0.01, 0.018));
  p.inertia = J.asDiagonal();
  p.arm_length_m = v.get_double("arm_length_m", 0.2);
  const std::string layout = v.get_string("layout", "x");
  std::vector<double> k = {1e-7, 1e-7, 1e-7, 1e-7};
  if (v.has("thrust_coefficients")) k = v.get_doubles("thrust_coefficients");
  else v.get_raw("thrust_coefficients");
  std::vector<int> dirs;
  if (v.has("rotor_directions")) {
    for (double d : v.get_doubles("rotor_directions")) dirs.push_back(static_cast<int>(d));
  } else {
    v.get_raw("rotor_directions");
  }
  const double torque_ratio = v.get_double("torque_to_thrust_m", 0.016);
  p.motor_time_constant_s = v.get_double("motor_time_constant_s", 0.03);
  s->rotor_unit = v.get_string("rotor_speed_unit", "rpm");
  p.rotor_speed_min = v.get_double("rotor_speed_min", 0.0);
  p.rotor_speed_max = v.get_double("rotor_speed_max", 1e5);
  p.linear_drag = v.get_vec3("linear_drag", Eigen::Vector3d::Zero());
  // Mass-normalized rotor drag D [1/s] (drag acceleration -D v_I): linear_drag = m D.
  const bool per_mass = v.has("rotor_drag_per_s");
  const Eigen::Vector3d D = v.get_vec3("rotor_drag_per_s", Eigen::Vector3d::Zero());
  v.check_unknown();
  if (per_mass) {
    if (v.has("linear_drag")) v.fail("rotor_drag_per_s", "give either linear_drag [N/(m/s)] or rotor_drag_per_s [1/s], not both");
    if (D.minCoeff() < 0.0) v.fail("rotor_drag_per_s", "must be >= 0");
    p.linear_drag = p.mass_kg * D;
  }
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

void parse_controller(const io::YamlMap& c, ControllerGains* g) {
  g->kp = c.get_vec3("kp", g->kp);
  g->kv = c.get_vec3("kv", g->kv);
  g->ki = c.get_vec3("ki", g->ki);
  g->kr = c.get_vec3("kr", g->kr);
  g->kw = c.get_vec3("kw", g->kw);
  g->integral_limit = c.get_double("integral_limit", g->integral_limit);
  g->disturbance_tau_s = c.get_double("disturbance_tau_s", g->disturbance_tau_s);
  c.check_unknown();
}

}  // namespace vid::sim::detail
