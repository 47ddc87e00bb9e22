#include "vid_system/input_checks.h"

#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <vector>

#include "io/csv_reader.h"
#include "io/errors.h"
#include "types/median.h"

namespace vid::system {

namespace fs = std::filesystem;

namespace {
/// The file the IMU calibration came from: the dataset's imu0/sensor.yaml or a preset's imu.yaml.
bool imu_from_dataset(const SystemConfig& cfg) {
  const auto it = cfg.sources.find("imu");
  return it == cfg.sources.end() || it->second.rfind("dataset", 0) == 0;
}

/// Rate [Hz] of the median of positive sample intervals (robust to a dropped sample or a gap).
std::optional<double> rate_of(std::vector<TimeNs>& intervals) {
  if (intervals.size() < 2) return std::nullopt;
  return 1e9 / static_cast<double>(upper_median(intervals));
}
}  // namespace

std::optional<double> median_rate_hz(const fs::path& csv, std::size_t max_rows) {
  std::vector<TimeNs> intervals;
  try {
    io::CsvReader reader(csv);
    std::optional<TimeNs> last;
    while (reader.rows() < max_rows && reader.next_row()) {
      const TimeNs t = reader.get_int(0, "timestamp [ns]");
      if (last && t > *last) intervals.push_back(t - *last);
      last = t;
    }
  } catch (const std::exception&) {
    // a malformed row: the reader names it; the rows before it still give the rate
  }
  return rate_of(intervals);
}

void check_imu_rate(const SystemConfig& cfg, double measured_hz, const fs::path& imu_yaml, const std::string& data) {
  const double used = cfg.estimator.imu_rate_hz;
  if (std::abs(used / measured_hz - 1.0) <= 0.10) return;
  const std::string stamps =
      fmt::format("{} is sampled at {:.4g} Hz (median interval {:.3f} ms)", data, measured_hz, 1e3 / measured_hz);
  if (!cfg.imu) {
    const auto it = cfg.sources.find("estimator");
    const std::string from = it == cfg.sources.end() || it->second == "defaults" ? "the estimator's default"
                                                                                 : it->second;
    throw io::DatasetError(fmt::format("{}: missing, so the IMU rate is imu_rate_hz {:g} Hz ({}), but {}; add "
                                       "imu0/sensor.yaml with rate_hz: {:.4g}",
                                       imu_yaml.string(), used, from, stamps, measured_hz));
  }
  if (imu_from_dataset(cfg))
    throw io::DatasetError(fmt::format("{}: rate_hz {:g} Hz, but {}; set rate_hz: {:.4g}", imu_yaml.string(), used,
                                       stamps, measured_hz));
  throw io::DatasetError(fmt::format("{}: update_rate {:g} Hz, but {}; set update_rate: {:.4g}",
                                     cfg.sources.at("imu"), used, stamps, measured_hz));
}

void check_imu_extrinsic(const SystemConfig& cfg, const fs::path& imu_yaml) {
  if (!cfg.imu || cfg.imu->T_BS.matrix().isIdentity(1e-9)) return;
  const std::string where = imu_from_dataset(cfg) ? imu_yaml.string() + ": key 'T_BS'"
                                                  : cfg.sources.at("imu") + ": key 'imu0.T_i_b'";
  throw io::ConfigError(where +
                        ": not the identity; the IMU frame is the body frame here and the estimator does not apply "
                        "an IMU extrinsic (express imu0 and the camera T_BS in the IMU frame)");
}

void ImuRateWatch::add(TimeNs t, const SystemConfig& cfg) {
  if (done_) return;
  if (last_ && t > *last_) intervals_.push_back(t - *last_);
  last_ = t;
  if (intervals_.size() < kSamples) return;
  done_ = true;
  check_imu_rate(cfg, *rate_of(intervals_), imu_yaml_, data_);
}

}  // namespace vid::system
