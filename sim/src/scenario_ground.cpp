/// @file scenario_ground.cpp
/// @brief `ground:` (floor contact of the landing gear) and `takeoff_landing:` (start and end
/// at rest on the floor) sections of a scenario.

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "scenario_parts.h"
#include "sim/render/scene_config.h"

namespace vid::sim::detail {

namespace {

void parse_contact(const io::YamlMap& g, const Scenario& s, GroundContactConfig* c) {
  c->enabled = true;
  c->gear_length_m = g.get_double("gear_length_m", c->gear_length_m);
  c->gear_half_span_m = g.get_vec2("gear_half_span_m", c->gear_half_span_m);
  c->stiffness_N_per_m = g.get_double("stiffness_N_per_m", c->stiffness_N_per_m);
  c->damping_Ns_per_m = g.get_double("damping_Ns_per_m", c->damping_Ns_per_m);
  c->damping_ramp_m = g.get_double("damping_ramp_m", c->damping_ramp_m);
  c->friction_coefficient = g.get_double("friction_coefficient", c->friction_coefficient);
  g.check_unknown();
  if (!(c->gear_length_m > 0.0)) g.fail("gear_length_m", "must be > 0");
  if (!(c->gear_half_span_m.minCoeff() > 0.0)) g.fail("gear_half_span_m", "must be > 0");
  if (!(c->stiffness_N_per_m > 0.0)) g.fail("stiffness_N_per_m", "must be > 0");
  if (!(c->damping_Ns_per_m >= 0.0)) g.fail("damping_Ns_per_m", "must be >= 0");
  if (!(c->damping_ramp_m >= 0.0)) g.fail("damping_ramp_m", "must be >= 0");
  if (!(c->friction_coefficient >= 0.0)) g.fail("friction_coefficient", "must be >= 0");
  // The gear must carry the vehicle with a small sag.
  const double sag = s.vehicle.mass_kg * s.vehicle.gravity / c->stiffness_N_per_m;
  if (!(sag < 0.1 * c->gear_length_m))
    g.fail("stiffness_N_per_m", "too soft: the gear sags " + std::to_string(sag * 1e3) +
                                    " mm under the weight (need < 10 % of gear_length_m)");
  // RK4 at max_step_s must resolve the contact. Per unit of gear stiffness / damping, the
  // vertical mode goes with 1/m, rolling / pitching / yawing on the feet with (lever arm)^2 / J
  // (normal forces at +-sx, +-sy; friction gear_length below the CoM). The fastest of them must
  // stay well inside RK4's stability region (|h lambda| < 2.8): oscillation omega h < 1,
  // damping rate h c / m_eff < 2.
  const double sx2 = std::pow(c->gear_half_span_m.x(), 2), sy2 = std::pow(c->gear_half_span_m.y(), 2);
  const double L2 = std::pow(c->gear_length_m, 2);
  const Eigen::Matrix3d& J = s.vehicle.inertia;
  const double per_unit = std::max({1.0 / s.vehicle.mass_kg, (sy2 + L2) / J(0, 0), (sx2 + L2) / J(1, 1), (sx2 + sy2) / J(2, 2)});
  const double h = s.physics_max_step_s;
  const double omega_h = std::sqrt(c->stiffness_N_per_m * per_unit) * h;
  const double damping_h = c->damping_Ns_per_m * per_unit * h;
  if (!(omega_h < 1.0))
    g.fail("stiffness_N_per_m", "too stiff for physics.max_step_s: the fastest contact mode turns " +
                                    std::to_string(omega_h) + " rad per step (need < 1)");
  if (!(damping_h < 2.0))
    g.fail("damping_Ns_per_m", "too much damping for physics.max_step_s: h c / m_eff = " + std::to_string(damping_h) +
                                   " (need < 2)");
  // The contact plane is the scene's floor.
  const SceneConfig scene = parse_scene_config(s.scene_node, s.file);
  const double floor_z = scene.room_center.z() - 0.5 * scene.room_size.z();
  if (std::abs(floor_z) > 1e-9)
    g.fail("gear_length_m", "the ground plane is z = 0 but the scene's floor is at z = " + std::to_string(floor_z) +
                                " (set scene.room_center z to half of room_size z)");
}

void parse_schedule(const io::YamlMap& t, TakeoffLandingConfig* c) {
  c->enabled = true;
  const auto positive = [&t](const char* key, double* v, bool allow_zero) {
    *v = t.get_double(key, *v);
    if (!(allow_zero ? *v >= 0.0 : *v > 0.0)) t.fail(key, allow_zero ? "must be >= 0" : "must be > 0");
  };
  positive("rest_start_s", &c->rest_start_s, true);
  positive("idle_s", &c->idle_s, true);
  positive("spin_up_s", &c->spin_up_s, false);
  positive("climb_speed_mps", &c->climb_speed_mps, false);
  positive("hover_s", &c->hover_s, true);
  positive("descent_speed_mps", &c->descent_speed_mps, false);
  positive("land_detect_s", &c->land_detect_s, false);
  positive("spin_down_s", &c->spin_down_s, false);
  positive("rest_end_s", &c->rest_end_s, true);
  t.check_unknown();
  if (c->descent_speed_mps > 1.0) t.fail("descent_speed_mps", "must be <= 1 m/s (a touchdown, not a crash)");
}

}  // namespace

void parse_ground(const io::YamlMap& root, Scenario* s) {
  if (root.has("ground")) {
    parse_contact(root.get_map_or_empty("ground"), *s, &s->environment.ground);
  } else {
    root.get_raw("ground");
  }
  if (root.has("takeoff_landing")) {
    const io::YamlMap t = root.get_map_or_empty("takeoff_landing");
    parse_schedule(t, &s->takeoff_landing);
    if (!s->environment.ground.enabled) root.fail("takeoff_landing", "needs a `ground:` section (the floor to rest on)");
    if (!(s->vehicle.rotor_speed_min > 0.0))
      root.fail("takeoff_landing", "needs vehicle.rotor_speed_min > 0 (the idle speed of an armed rotor)");
  } else {
    root.get_raw("takeoff_landing");
  }
}

}  // namespace vid::sim::detail
