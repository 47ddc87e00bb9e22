#pragma once
/// @file input_checks.h
/// @brief Checks of a run's calibration against its data before the first measurement is used
/// (docs/bad_inputs.md, issue #52): values that are read but would otherwise be silently wrong.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vid_system/config.h"

namespace vid::system {

/// @brief Median sample rate [Hz] of the first @p max_rows rows of a sensor CSV (timestamp in
/// column 1). Stops quietly at the first malformed row (the dataset reader reports it with its
/// line); nullopt when fewer than two positive intervals were read.
std::optional<double> median_rate_hz(const std::filesystem::path& csv, std::size_t max_rows = 2000);

/// @brief Throw io::DatasetError when the IMU rate the estimator uses (it discretizes the IMU
/// noise) differs from @p measured_hz by more than 10 %. The line names the file the rate came
/// from (@p imu_yaml, a preset's imu.yaml) or, when there is none, @p imu_yaml as missing and
/// the estimator's imu_rate_hz, and @p data (what the stamps were measured on).
void check_imu_rate(const SystemConfig& cfg, double measured_hz, const std::filesystem::path& imu_yaml,
                    const std::string& data);

/// @brief Throw io::ConfigError when the IMU calibration's extrinsic (imu0/sensor.yaml T_BS, a
/// preset imu.yaml's T_i_b) is not the identity: the IMU frame is the body frame here and the
/// estimator does not apply it (docs/formats.md §2).
void check_imu_extrinsic(const SystemConfig& cfg, const std::filesystem::path& imu_yaml);

/// @brief check_imu_rate on a live stream: the median rate of the first kSamples IMU stamps is
/// checked once (vid_live, whose IMU arrives as messages).
class ImuRateWatch {
 public:
  static constexpr std::size_t kSamples = 200;
  ImuRateWatch(std::filesystem::path imu_yaml, std::string data) : imu_yaml_(std::move(imu_yaml)), data_(std::move(data)) {}
  /// @brief One IMU stamp; throws as check_imu_rate once kSamples arrived and the rates disagree.
  void add(TimeNs t, const SystemConfig& cfg);

 private:
  std::filesystem::path imu_yaml_;
  std::string data_;
  std::optional<TimeNs> last_;
  std::vector<TimeNs> intervals_;
  bool done_ = false;
};

}  // namespace vid::system
