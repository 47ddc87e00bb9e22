#pragma once
/// @file replay.h
/// @brief vid_replay: publish a dataset folder on LCM (IMU, camera images as mono8 image_t,
/// rotor speeds / thrust) at a real-time factor or as fast as possible, optionally writing an
/// LCM event log, with optional fault injection for testing vid_live.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "io/lcm/channels.h"

namespace vid::replay {

/// @brief Faults injected into the published stream (all off by default).
struct FaultOptions {
  double drop_images = 0.0;      ///< probability that an image message is not published
  double duplicate_imu = 0.0;    ///< probability that an IMU message is published twice
  double reorder = 0.0;          ///< probability that a message is delayed (any stream)
  double reorder_max_ms = 20.0;  ///< delay of a reordered message: uniform in (0, max]
  int malformed = 0;             ///< undecodable / invalid messages spread over the run
  double late = 0.0;             ///< probability that a message is delayed by late_ms (any stream)
  double late_ms = 100.0;        ///< delay of a late message (beyond the receiver's reorder window)
  double stall_start_s = -1.0;   ///< camera stall: no image from this time (s after the first measurement)
  double stall_s = 0.0;          ///< ... for this long
  std::uint64_t seed = 1;
};

/// @brief Settings of one replay.
struct ReplayOptions {
  std::filesystem::path dataset;
  std::string lcm_url;                      ///< empty: only write the log
  double rate = 1.0;                        ///< real-time factor (ignored when fast)
  bool fast = false;                        ///< publish as fast as possible
  std::optional<std::filesystem::path> log; ///< LCM event log to write (lcm-logplayer format)
  double start_s = 0.0;                     ///< relative to the first measurement
  std::optional<double> end_s;              ///< none: to the end
  lcm_io::ChannelNames channels;
  FaultOptions faults;
  /// Passes over the [start, end] window (soak tests). Pass k is shifted by k * P with P the
  /// window's IMU span (last - first IMU time); a pass other than the last publishes the
  /// measurements in [first, first + P), so streams on a common clock (the simulator's) stay
  /// exactly regular across the seam. Each pass injects its own faults (options are per pass).
  int loops = 1;
  bool progress = true;
  /// Significant bits of 16-bit images (published as mono8 scaled by 2^(bits-8)); 0 = auto
  /// per camera stream from sample images (system::camera_bit_depths), as vid_run decodes them.
  int image_bit_depth = 0;
  /// Publish without the camera (IMU, rotors / thrust only), said in one warning line; without
  /// it a folder with no cam0/ images (e.g. feature-level feat0/ data) is refused.
  bool no_camera = false;
};

/// @brief Publish the dataset. Returns a report: messages per channel and every injected
/// fault (as vid_live should count them: dropped images per camera, duplicated IMU messages,
/// reordered arrivals per stream, late messages per stream, malformed messages per channel,
/// images withheld by a camera stall per camera).
/// @throws io::DatasetError / std::runtime_error on bad input or an unusable LCM URL / log
nlohmann::json replay(const ReplayOptions& options, const std::atomic<bool>& stop);

}  // namespace vid::replay
