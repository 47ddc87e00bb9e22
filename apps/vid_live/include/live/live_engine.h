#pragma once
/// @file live_engine.h
/// @brief vid_live's engine: raw LCM payloads in (from the LCM thread), decoded and put in
/// order by a reorder window, queued (bounded: under overload the oldest camera frames are
/// dropped, never IMU), run by a worker thread through the same vid_system System as vid_run, with
/// estimates, force and health published on LCM.

#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "io/dataset_reader.h"
#include "io/lcm/channels.h"
#include "io/lcm/lcm_convert.h"
#include "live/camera_watch.h"
#include "live/live_types.h"
#include "live/reorder_window.h"
#include "vid_system/input_checks.h"
#include "vid_system/system.h"

namespace vid::live {

/// @brief Settings of a live run.
struct LiveOptions {
  system::SystemOptions session;           ///< out_dir, preset, mode, init (features = images)
  io::DatasetCalibration calibration;      ///< sensor files (cameras, IMU, rotors, vehicle)
  lcm_io::ChannelNames channels;
  TimeNs reorder_window_ns = 30'000'000;   ///< data time a message waits for late-comers
  std::size_t max_queued_frames = 4;       ///< camera frames waiting for the worker
  std::size_t max_queued_samples = 100000; ///< IMU/rotor/thrust samples waiting (then the reader waits)
  bool block_when_full = false;            ///< true: the LCM thread waits instead of dropping (logs)
  double stall_s = 0.5;                    ///< no camera frame for this long (data time) = stall
  double no_camera_s = 3.0;                ///< no camera frame at all in this much IMU data time = no_camera
  std::string source_url;                  ///< recorded in the summary
  double lag_s = 0.0;                      ///< > 0: fixed-lag smoothing, published on the *_LAGGED channels
  std::filesystem::path imu_yaml = "imu0/sensor.yaml";  ///< named when the IMU rate disagrees (--sensors)
};

/// @brief Health of the estimator as published.
using lcm_io::Health;

/// @brief The live estimator. on_message() is called by one thread (the LCM handler thread);
/// the engine runs the estimator on its own worker thread.
class LiveEngine {
 public:
  /// @param publisher  LCM instance to publish VID_STATE / VID_FORCE / VID_STATUS on (may be null)
  LiveEngine(LiveOptions options, lcm::LCM* publisher);
  ~LiveEngine();
  LiveEngine(const LiveEngine&) = delete;
  LiveEngine& operator=(const LiveEngine&) = delete;

  /// @brief Start the worker thread (messages received before are queued, frames bounded as
  /// usual). finish() starts it too.
  void start();
  /// @brief True when the estimator runs in dynamics mode (the force is estimated).
  bool dynamics() const { return session_->dynamics(); }
  /// @brief Channels to subscribe to (IMU, cameras tracked, rotors or thrust).
  std::vector<std::string> input_channels() const;
  /// @brief Subscribe the engine to its input channels on @p lcm.
  void subscribe(lcm::LCM& lcm);
  /// @brief LCM raw-buffer handler (forwards to on_message).
  void on_raw(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  /// @brief One raw payload from @p channel (decoding failures are counted, never thrown).
  void on_message(const std::string& channel, const void* data, std::size_t size);
  /// @brief End of input: release everything held, let the worker finish, join it. Idempotent.
  /// @throws std::runtime_error when the worker stopped on an error (e.g. an unwritable output)
  void finish();
  /// @brief True once the worker has stopped on an error (the input loop should end).
  bool failed() const { return failed_.load(); }
  /// @brief summary.json content (System summary + live fields). Call after finish(): the
  /// worker owns the System while it runs.
  nlohmann::json summary() const;
  /// @brief Write DIR/summary.json (summary() plus @p extra's fields) when an output folder was given.
  void write_summary(const nlohmann::json& extra = nlohmann::json::object()) const;
  /// @brief Health now.
  Health health() const;
  /// @brief Estimates published so far.
  long published_states() const;
  /// @brief True when the input had IMU data and not one camera frame (status no_camera). After finish().
  bool camera_never_delivered() const;
  /// @brief Payloads received on the input channels so far (decoded or not).
  const std::atomic<long>& message_count() const { return messages_; }

 private:
  void deliver(std::vector<LiveItem> items, std::unique_lock<std::mutex>& lock);
  void push_work(WorkItem w, std::unique_lock<std::mutex>& lock);
  void worker_loop();
  void process(WorkItem& w);
  void publish_estimate(const system::System& s, const EstimateOutput& e);
  /// @brief state_t of @p e with the health and re-initialization count of now (locks the mutex).
  state_t state_now(const EstimateOutput& e);
  /// @brief A fixed-lag smoothed estimate (LiveOptions::lag_s) on the *_LAGGED channels.
  void publish_lagged(const system::System& s, const EstimateOutput& e);
  void publish_status_locked(TimeNs t);
  std::vector<std::pair<std::string, std::int64_t>> counters() const;  // under mutex_
  Health health_locked() const;

  LiveOptions opt_;
  lcm::LCM* pub_;
  std::unique_ptr<system::System> session_;
  int tracked_cameras_ = 1;
  bool use_rotor_ = false, use_thrust_ = false;
  int rotor_count_ = 0;
  std::string rotor_unit_;

  mutable std::mutex mutex_;
  std::condition_variable cv_work_, cv_space_;
  ReorderWindow window_;
  std::deque<WorkItem> queue_;
  std::size_t queued_frames_ = 0;
  bool input_done_ = false, finished_ = false, started_ = false;
  std::int64_t frames_dropped_overload_ = 0, frames_without_left_ = 0, camera_stalls_ = 0;
  std::thread worker_;
  std::atomic<long> messages_{0};
  std::atomic<bool> failed_{false};
  std::string error_;
  int malformed_warnings_ = 0;

  // Worker-thread state (read by summary()/health() under mutex_).
  Health health_ = Health::kInitializing;
  int reinit_count_ = 0;
  nlohmann::json divergences_ = nlohmann::json::array();  // {t_ns, message} each, as vid_run's
  long published_ = 0;
  long published_lagged_ = 0;
  bool stalled_ = false;
  std::optional<TimeNs> first_t_, last_t_, last_frame_t_, last_status_t_;
  std::optional<system::ImuRateWatch> imu_rate_;  ///< worker thread only
  CameraWatch camera_watch_{3.0};                   ///< written by the worker under mutex_
  std::map<TimeNs, SteadyClock::time_point> frame_arrival_;     ///< frames pushed, not yet processed
  std::vector<SteadyClock::time_point> processed_arrivals_;     ///< processed, awaiting a state
  system::StageStats latency_ms_;
  SteadyClock::time_point wall_start_;
};

}  // namespace vid::live
