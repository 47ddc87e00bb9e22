#pragma once
/// @file config.h
/// @brief The System's typed parameters (SystemParams), and where a program takes them from: a
/// config preset (folder or estimator.yaml) when given, else the dataset's own sensor.yaml /
/// vehicle.yaml and estimator defaults (resolve_config), with the mode and initialization
/// decided from the command line and the streams present (make_system_params).
///
/// A preset folder may hold: estimator.yaml (EstimatorParams keys), frontend.yaml
/// (FrontendParams keys), imu.yaml (Kalibr imu chain), camchain.yaml or camchain-imucam.yaml
/// (Kalibr imucam chain), vehicle.yaml, rotor_sensor.yaml. Every file is optional; what a preset lacks comes from the dataset.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "frontend/frontend_params.h"
#include "io/dataset_reader.h"
#include "types/calibration.h"
#include "vio_core/estimator_params.h"

namespace vid::system {

/// @brief Where features come from: the KLT frontend on images, or a dataset's feat0 stream
/// (undistorted here). kAuto is for command lines (vid_run decides from the dataset); a System
/// takes kImages or kFeat0.
enum class FeatureSource { kAuto, kImages, kFeat0 };

/// @brief Every calibration and parameter file of a run, with the file each part came from.
struct SystemConfig {
  EstimatorParams estimator;
  FrontendParams frontend;
  std::vector<CameraCalib> cameras;
  std::optional<ImuNoise> imu;
  std::optional<RotorSensor> rotor;
  std::optional<VehicleParams> vehicle;
  /// mode the preset's estimator.yaml sets explicitly (`mode:` key); nullopt when it has no
  /// such key, so the program picks the mode from the input's streams
  std::optional<PropagationMode> preset_mode;
  std::map<std::string, std::string> sources;  ///< part -> file (or "defaults")
  /// One fact, one file: a value estimator.yaml sets that the IMU calibration (noise, rate) or
  /// vehicle.yaml (gravity) replaces with a different one, one line each (warned by System,
  /// summary.json config_overrides).
  std::vector<std::string> overrides;
};

/// @brief Resolve the configuration. IMU noise comes from the IMU calibration (preset
/// imu.yaml, else the dataset's imu0/sensor.yaml) when one exists; gravity from vehicle.yaml;
/// an estimator.yaml value they replace with another is listed in SystemConfig::overrides.
/// @param config  preset folder, or its estimator.yaml; std::nullopt for dataset-only
/// @throws io::ConfigError naming the file and key at fault
SystemConfig resolve_config(const std::optional<std::filesystem::path>& config, const io::DatasetCalibration& dataset);

/// @brief The configuration as YAML text (summary.json's config_yaml).
std::string describe(const SystemConfig& cfg);

/// @brief The same configuration as a JSON object (summary.json's config): estimator, cameras,
/// imu, rotor, vehicle (the parts present; summary.json's config_sources names their files).
nlohmann::json describe_json(const SystemConfig& cfg);

/// @brief The typed parameters a System is built from (programs get them from
/// make_system_params, tests build them in code).
struct SystemParams {
  /// estimator (mode and init_mode decided), frontend, calibrations; cameras must not be empty
  SystemConfig config;
  std::string mode_source = "parameters";           ///< where the mode came from (summary.json)
  FeatureSource features = FeatureSource::kImages;  ///< kImages or kFeat0 (not kAuto)
  std::optional<std::filesystem::path> out_dir;     ///< docs/formats.md §2 files; nullopt: none
  /// also write out_dir/tracks.csv: the frontend's tracked features per frame, vid_track's format
  /// (for viewing a run: `vid-eval view`)
  bool write_tracks = false;
  /// vehicle of the input's ground truth: its mass turns force0 [N] into m/s^2 for the force
  /// metrics when no mass0 stream is pushed (the dataset's own vehicle.yaml)
  std::optional<VehicleParams> truth_vehicle;
  /// thrust0 and rotor0 both present: thrust0 is the thrust, rotor speeds are not used
  bool ignore_rotor_speeds = false;
};

/// @brief What a program knows before the first measurement (command line, streams present).
struct SystemOptions {
  std::optional<std::filesystem::path> out_dir;  ///< nullopt: no output files
  bool write_tracks = false;                     ///< also out_dir/tracks.csv (SystemParams::write_tracks)
  std::optional<std::filesystem::path> config;   ///< preset folder or its estimator.yaml
  std::optional<PropagationMode> mode;           ///< nullopt: preset `mode:`, else auto
  std::optional<InitMode> init;
  FeatureSource features = FeatureSource::kImages;  ///< kImages or kFeat0 (not kAuto)
  bool has_rotor = false;   ///< rotor speeds will be pushed
  bool has_thrust = false;  ///< thrust will be pushed
  std::string context;      ///< names the input in error messages (dataset path, LCM URL)
};

/// @brief Resolve the files (resolve_config) and decide the mode: the option, else the preset's
/// explicit `mode:`, else dynamics when rotor speeds or thrust will be pushed.
/// @throws std::runtime_error / io::ConfigError when the configuration cannot run
SystemParams make_system_params(const SystemOptions& options, const io::DatasetCalibration& calibration);

}  // namespace vid::system
