#pragma once
/// @file live_types.h
/// @brief Items that flow from the LCM handlers through the reorder window to the estimator
/// worker, and the fault counters of one stream.

#include <chrono>
#include <cstdint>
#include <string>
#include <variant>

#include <opencv2/core.hpp>

#include "types/measurements.h"

namespace vid::live {

using SteadyClock = std::chrono::steady_clock;

/// @brief Input streams. The order is the tie order at equal timestamps, the same as the
/// dataset reader's (imu0, rotor0, thrust0, images), so replayed data runs exactly as vid_run.
enum class Stream : int { kImu = 0, kRotor = 1, kThrust = 2, kCam0 = 3, kCam1 = 4 };
inline constexpr int kNumStreams = 5;
/// @brief "imu", "rotors", "thrust", "cam0", "cam1".
std::string stream_name(Stream s);

/// @brief One camera image as received (8-bit mono, owns its pixels).
struct CameraImage {
  TimeNs t_ns = 0;
  int cam_id = 0;
  cv::Mat image;
};

/// @brief One stereo (or mono) camera frame assembled from the images of one timestamp.
struct CameraFrame {
  TimeNs t_ns = 0;
  cv::Mat left, right;  ///< right empty when cam1 is absent
  SteadyClock::time_point arrival;  ///< when its last image arrived (latency reference)
};

/// @brief A decoded input message.
struct LiveItem {
  Stream stream = Stream::kImu;
  TimeNs t_ns = 0;
  SteadyClock::time_point arrival;
  std::variant<ImuSample, RotorSample, ThrustSample, CameraImage> data;
};

/// @brief What the worker runs: sensor samples and assembled camera frames, in time order.
using WorkItem = std::variant<ImuSample, RotorSample, ThrustSample, CameraFrame>;

/// @brief Fault counters of one input stream.
struct StreamCounters {
  std::int64_t received = 0;    ///< messages that decoded
  std::int64_t malformed = 0;   ///< payloads that failed to decode or validate
  std::int64_t duplicate = 0;   ///< same timestamp as a message already seen (dropped)
  std::int64_t reordered = 0;   ///< arrived after a later message of any stream (accepted)
  std::int64_t late = 0;        ///< older than what the window had already released (dropped)
  std::int64_t missing = 0;     ///< gaps in the stream: messages that never arrived
};

}  // namespace vid::live
