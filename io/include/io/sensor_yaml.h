#pragma once
/// @file sensor_yaml.h
/// @brief The dataset folder's own YAML files (docs/formats.md §1): EuRoC camN/ and imu0/sensor.yaml,
/// rotor0/sensor.yaml and vehicle.yaml. Strict loaders (ConfigError naming file, line and key)
/// and writers whose text the loaders read back exactly (every struct prints itself).

#include <filesystem>
#include <ostream>
#include <string>

#include "io/errors.h"
#include "io/strict_yaml.h"
#include "types/calibration.h"

namespace vid::io {

/// @brief Parse a distortion model name: radial-tangential | radtan | equidistant | equi | none.
/// Returns false for anything else.
bool parse_distortion_model(const std::string& name, DistortionModel* model);
/// @brief EuRoC name of a model ("radial-tangential", "equidistant", "none").
std::string euroc_name(DistortionModel model);
/// @brief Kalibr name of a model ("radtan", "equidistant", "none").
std::string kalibr_name(DistortionModel model);

/// @brief A 4x4 from a YAML key as a rigid transform; ConfigError unless the rotation is
/// orthonormal (1e-6), det +1 and the last row is [0 0 0 1].
Eigen::Isometry3d get_rigid_transform(const YamlMap& map, const std::string& key);

/// @brief camN/sensor.yaml (EuRoC keys; optional extension key timeshift_cam_imu).
CameraCalib load_camera_yaml(const std::filesystem::path& path, int cam_id);
/// @brief imu0/sensor.yaml (EuRoC keys).
ImuNoise load_imu_yaml(const std::filesystem::path& path);
/// @brief rotor0/sensor.yaml (sensor_type, unit, count, rate_hz, noise_density).
RotorSensor load_rotor_yaml(const std::filesystem::path& path);
/// @brief vehicle.yaml (mass_kg, gravity, rotor_thrust_coefficients).
VehicleParams load_vehicle_yaml(const std::filesystem::path& path);

/// @brief Text of camN/sensor.yaml in EuRoC's layout (load_camera_yaml reads it back exactly).
std::string to_yaml(const CameraCalib& cam);
/// @brief Text of imu0/sensor.yaml in EuRoC's layout.
std::string to_yaml(const ImuNoise& imu);
/// @brief Text of rotor0/sensor.yaml.
std::string to_yaml(const RotorSensor& rotor);
/// @brief Text of vehicle.yaml.
std::string to_yaml(const VehicleParams& vehicle);

/// @brief Write @p text to @p path (creating parent folders); DatasetError on failure.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace vid::io

namespace vid {
/// @brief Print as the YAML the loaders read (so a run can record its exact configuration).
std::ostream& operator<<(std::ostream& os, const CameraCalib& cam);
std::ostream& operator<<(std::ostream& os, const ImuNoise& imu);
std::ostream& operator<<(std::ostream& os, const RotorSensor& rotor);
std::ostream& operator<<(std::ostream& os, const VehicleParams& vehicle);
}  // namespace vid
