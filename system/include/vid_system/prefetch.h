#pragma once
/// @file prefetch.h
/// @brief Reads a dataset in time order and decodes its images ahead of the consuming thread
/// (vid_run: while the frontend and estimator work; vid_replay: ahead of a real-time schedule).
/// The consumer gets the same measurements in the same order whatever the number of threads.

#include <array>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "io/dataset_reader.h"

namespace vid::system {

/// @brief One measurement; for an ImageFrame its cam 0 / cam 1 images decoded to 8-bit mono.
struct Prefetched {
  Measurement m;
  TimeNs t0 = 0;  ///< time of the dataset's first measurement (reference of start/end)
  /// (cam_id, image) for each image of the frame with cam_id <= 1, in the frame's order; an
  /// empty Mat for an unreadable image (see vid::decode_gray8)
  std::vector<std::pair<int, cv::Mat>> images;
  double decode_ms = 0.0;      ///< wall time of decoding this frame's images (on the decoding thread)
  double decode_cpu_ms = 0.0;  ///< CPU time of the decoding thread for them
};

/// @brief How far and with how many threads to read ahead.
struct PrefetchOptions {
  double start_s = 0.0;  ///< window start [s] after the first measurement
  double end_s = -1.0;   ///< window end [s] after the first measurement; < 0: to the end
  /// Threads that decode images; 0: no background work at all, next() reads and decodes inline.
  /// With n > 0 one more thread reads the dataset files.
  int decode_threads = 1;
  std::size_t capacity = 256;  ///< measurements queued ahead at most
  std::size_t max_frames = 0;  ///< camera frames queued ahead at most (0: only `capacity` bounds)
  /// Nice increment of the background threads (Linux, per thread; 0: unchanged). When cores are
  /// short, the consumer then runs first and the decoders use what is left, so decode-ahead
  /// does not stretch the consumer's per-frame wall time.
  int background_nice = 0;
  /// Significant bits of each camera's 16-bit images (vid::decode_gray8), index cam_id 0 / 1;
  /// fixed for the run (see vid_system/image_depth.h).
  std::array<int, 2> image_bits{16, 16};
};

/// @brief Totals over the run (for summary.json).
struct PrefetchStats {
  long frames_decoded = 0;         ///< also frames decoded ahead but never taken
  double decode_cpu_ms = 0.0;      ///< CPU time of all decoding
  double consumer_wait_ms = 0.0;   ///< wall time next() waited for the reader / decoders
};

/// @brief Dataset reader with decode-ahead over [first + start_s, first + end_s].
class Prefetcher {
 public:
  Prefetcher(io::DatasetReader& reader, const PrefetchOptions& options);
  ~Prefetcher();
  Prefetcher(const Prefetcher&) = delete;
  Prefetcher& operator=(const Prefetcher&) = delete;

  /// @brief Wait until the read-ahead buffer is full or the data ends (pre-roll before a
  /// real-time schedule starts). Returns at once with decode_threads == 0.
  void wait_ready();
  /// @brief Next measurement in time order; nullopt at the end. Rethrows the reader's errors
  /// after the measurements read before them.
  std::optional<Prefetched> next();
  /// @brief Stop the background threads (each after the frame it is decoding) and join them;
  /// next() then returns what is already decoded. Idempotent; the destructor calls it.
  void stop();
  /// @brief Totals so far (final after stop()).
  PrefetchStats stats() const;

 private:
  struct Slot {
    Prefetched p;
    bool ready = false;
    std::exception_ptr error;  ///< thrown by decoding; rethrown by next() in this slot's turn
  };
  /// Reads the next measurement of the window (nullopt at its end); reader thread or inline.
  std::optional<Prefetched> read_one();
  void decode(Prefetched& p);
  void read_loop();
  void decode_loop();
  void lower_priority() const;

  io::DatasetReader& reader_;
  PrefetchOptions opt_;
  std::optional<TimeNs> t0_;
  TimeNs t_start_ = 0, t_end_ = 0;
  bool window_ended_ = false;

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::unique_ptr<Slot>> queue_;  ///< in time order; the front is taken when ready
  std::deque<Slot*> jobs_;                   ///< frames in queue_ waiting for a decoder
  std::size_t frames_queued_ = 0;
  bool reader_done_ = false, cancel_ = false;
  std::exception_ptr error_;
  PrefetchStats stats_;
  std::vector<std::thread> threads_;
};

}  // namespace vid::system
