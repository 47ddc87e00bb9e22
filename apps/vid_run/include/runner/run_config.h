#pragma once
/// @file run_config.h
/// @brief Where vid_run takes its settings from: a config preset (folder or estimator.yaml)
/// when given, else the dataset's own sensor.yaml / vehicle.yaml and estimator defaults.
///
/// A preset folder may hold: estimator.yaml (EstimatorParams keys), frontend.yaml
/// (FrontendParams keys), imu.yaml (Kalibr imu chain), camchain.yaml or camchain-imucam.yaml
/// (Kalibr imucam chain), vehicle.yaml, rotor_sensor.yaml. Every file is optional; what a preset lacks comes from the dataset.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "frontend/frontend_params.h"
#include "io/dataset_reader.h"
#include "vio_core/calibration.h"
#include "vio_core/estimator_params.h"

namespace vid::runner {

/// @brief Everything a run needs, with the file each part came from.
struct RunConfig {
  EstimatorParams estimator;
  FrontendParams frontend;
  std::vector<CameraCalib> cameras;
  std::optional<ImuNoise> imu;
  std::optional<RotorSensor> rotor;
  std::optional<VehicleParams> vehicle;
  /// mode the preset's estimator.yaml sets explicitly (`mode:` key); nullopt when it has no
  /// such key, so vid_run picks the mode from the dataset's streams
  std::optional<PropagationMode> preset_mode;
  std::map<std::string, std::string> sources;  ///< part -> file (or "defaults")
};

/// @brief Resolve the configuration. IMU noise comes from the IMU calibration (preset
/// imu.yaml, else the dataset's imu0/sensor.yaml) when one exists; gravity from vehicle.yaml.
/// @param config  preset folder, or its estimator.yaml; std::nullopt for dataset-only
/// @throws io::ConfigError naming the file and key at fault
RunConfig resolve_run_config(const std::optional<std::filesystem::path>& config,
                             const io::DatasetCalibration& dataset);

/// @brief The configuration as YAML text (recorded into summary.json).
std::string describe(const RunConfig& cfg);

}  // namespace vid::runner
