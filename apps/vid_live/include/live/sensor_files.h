#pragma once
/// @file sensor_files.h
/// @brief Calibration of a live setup from sensor files laid out as a dataset folder
/// (docs/formats.md §1) without the data: camN/sensor.yaml, imu0/sensor.yaml, rotor0/sensor.yaml, vehicle.yaml.

#include <filesystem>

#include "io/dataset_reader.h"

namespace vid::live {

/// @brief Load every sensor file present under DIR or DIR/mav0 (cameras cam0, cam1, ... in
/// order until the first missing one). Throws io::ConfigError / io::DatasetError naming the
/// file; std::runtime_error when DIR does not exist.
io::DatasetCalibration load_sensor_files(const std::filesystem::path& dir);

/// @brief DIR/mav0 when it exists, else DIR: the folder that holds imu0/, cam0/, ...
std::filesystem::path sensor_root(const std::filesystem::path& dir);

}  // namespace vid::live
