#pragma once
/// @file kalibr.h
/// @brief Kalibr calibration files: the imu chain (imu.yaml / kalibr_imu_chain.yaml) and the
/// imucam chain (camchain-imucam.yaml). Strict: Kalibr's (and OpenVINS') known keys are
/// accepted, anything else is a ConfigError naming file, line and key.

#include <filesystem>
#include <string>
#include <vector>

#include "io/errors.h"
#include "types/calibration.h"

namespace vid::io {

/// @brief Kalibr IMU noise file. Root either has an `imu0:` mapping or is flat (Kalibr's input
/// imu.yaml). update_rate -> rate_hz; T_i_b (body to IMU) is inverted into ImuNoise::T_BS.
/// model must be calibrated (OpenVINS: kalibr or rpng with identity Tw, Ta, R_IMUtoGYRO,
/// R_IMUtoACC and zero Tg) and time_offset 0: values the estimator would otherwise ignore.
ImuNoise load_kalibr_imu(const std::filesystem::path& path);

/// @brief Kalibr camchain-imucam: cam0, cam1, ... (contiguous). T_cam_imu is T_CI and is
/// inverted into CameraCalib::T_IC (OpenVINS' T_imu_cam = T_IC is taken as it is);
/// distortion_model radtan | equidistant; camera_model pinhole.
std::vector<CameraCalib> load_kalibr_imucam(const std::filesystem::path& path);

/// @brief Kalibr imu chain text for @p imu (load_kalibr_imu reads it back).
std::string to_kalibr_imu_yaml(const ImuNoise& imu);
/// @brief Kalibr imucam chain text for @p cams (load_kalibr_imucam reads it back; T_IC goes
/// through one inversion each way, so it returns to within ~1e-15).
std::string to_kalibr_imucam_yaml(const std::vector<CameraCalib>& cams);

}  // namespace vid::io
