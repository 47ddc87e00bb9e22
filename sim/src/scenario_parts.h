#pragma once
/// @file scenario_parts.h
/// @brief Section parsers of the scenario loader (private to sim).

#include <filesystem>

#include "sim/scenario.h"
#include "io/strict_yaml.h"

namespace vid::sim::detail {

void parse_vehicle(const io::YamlMap& v, Scenario* s);
void parse_controller(const io::YamlMap& c, ControllerGains* g);
void parse_trajectory(const io::YamlMap& t, const std::filesystem::path& base_dir, TrajectoryConfig* c);
void parse_forces(const io::YamlMap& f, EnvironmentConfig* e);
void parse_mass(const io::YamlMap& m, EnvironmentConfig* e);
void parse_sensors(const io::YamlMap& root, Scenario* s);
/// @brief `sensor_faults:` (needs the vehicle and the IMU rate already read).
void parse_sensor_faults(const io::YamlMap& f, Scenario* s);
/// @brief `ground:` and `takeoff_landing:` (needs the vehicle, physics and scene already read).
void parse_ground(const io::YamlMap& root, Scenario* s);
/// @brief Build a Scenario from a parsed (base-merged) root mapping; name = file for messages.
Scenario scenario_from_node(const YAML::Node& root, const std::string& name);

}  // namespace vid::sim::detail
