#pragma once
/// @file prefetch.h
/// @brief Reads a dataset and decodes its images on a background thread, ahead of the
/// publishing thread, so that real-time replay is not delayed by PNG decoding.

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "io/dataset_reader.h"

namespace vid::replay {

/// @brief One measurement with its images decoded to 8-bit mono (as vid_run decodes them;
/// an empty Mat for an unreadable image).
struct Prefetched {
  Measurement m;
  TimeNs t0 = 0;  ///< time of the dataset's first measurement (reference of start/end)
  std::vector<std::pair<int, cv::Mat>> images;  ///< (cam_id, image) of an ImageFrame, cams 0 and 1
};

/// @brief Background reader over [first + start_s, first + end_s] (end_s < 0: to the end).
class Prefetcher {
 public:
  /// @param capacity  measurements read ahead at most
  Prefetcher(io::DatasetReader& reader, double start_s, double end_s, std::size_t capacity = 256);
  ~Prefetcher();
  Prefetcher(const Prefetcher&) = delete;
  Prefetcher& operator=(const Prefetcher&) = delete;

  /// @brief Wait until the read-ahead buffer is full or the data ends (pre-roll before a
  /// real-time schedule starts).
  void wait_ready();
  /// @brief Next measurement in time order; nullopt at the end. Rethrows the reader's errors.
  std::optional<Prefetched> next();

 private:
  void run();

  io::DatasetReader& reader_;
  double start_s_, end_s_;
  std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Prefetched> queue_;
  bool done_ = false, cancel_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace vid::replay
