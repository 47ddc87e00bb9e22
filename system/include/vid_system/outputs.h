#pragma once
/// @file outputs.h
/// @brief Writers of the estimator-run outputs of docs/formats.md §2. Every row is flushed, so an
/// interrupted run keeps everything it had written.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "types/measurements.h"

namespace vid::system {

/// @brief One estimate as written to the outputs (IMU rate).
struct EstimateRow {
  TimeNs t_ns = 0;
  Pose T_WI;
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d F_ext_I = Eigen::Vector3d::Zero();  ///< mass-normalized, body [m/s^2]
  /// 1-sigma of [dtheta(3), dp(3), dv(3), db_g(3), db_a(3), dF_I(3)]; F is 0 in imu mode
  Eigen::Matrix<double, 18, 1> sigma = Eigen::Matrix<double, 18, 1>::Zero();
  double thrust_scale = 1.0;        ///< s of a = s T_m + F_ext + b_a (1 when not estimated)
  double sigma_thrust_scale = 0.0;  ///< its 1-sigma (0 when not estimated)
  double time_offset_s = 0.0;        ///< camera-IMU time offset in use [s]
  double sigma_time_offset_s = 0.0;  ///< its 1-sigma (0 when not estimated)
};

/// @brief One line of trajectory_tum.txt: "t tx ty tz qx qy qz qw", t in seconds with 9
/// decimals (exact for integer ns), the quaternion normalized.
std::string tum_line(const TimedPose& x);
/// @brief Start of the comment line that marks a re-initialization in a TUM trajectory
/// ("# re-initialized at <t s>: ..."); vid-eval scores each piece in its own frame.
inline constexpr const char* kTumReinitMarker = "# re-initialized at";
/// @brief The whole marker line for a re-initialization whose first estimate is at @p t_ns.
std::string tum_reinit_marker(TimeNs t_ns);

/// @brief Per camera frame stage times [ms].
struct TimingRow {
  TimeNs t_ns = 0;
  double tracking_ms = 0.0;
  double propagation_ms = 0.0;
  double accel_update_ms = 0.0;
  double msckf_update_ms = 0.0;
  double marginalization_ms = 0.0;
  double total_ms = 0.0;
};

/// @brief A CSV/text file that is flushed after every row and reports write errors by name.
class FlushedFile {
 public:
  FlushedFile() = default;
  explicit FlushedFile(const std::filesystem::path& path);
  ~FlushedFile();
  FlushedFile(const FlushedFile&) = delete;
  FlushedFile& operator=(const FlushedFile&) = delete;
  /// @brief Write one line (newline added) and flush; throws std::runtime_error naming the file.
  void line(const std::string& text);
  void close();

 private:
  std::filesystem::path path_;
  std::FILE* f_ = nullptr;
};

/// @brief trajectory_tum.txt, state.csv, force.csv and timing.csv in one output folder, and
/// mass.csv when the thrust scale is estimated.
class RunOutputs {
 public:
  /// @param write_force  false in imu mode (force.csv then holds only its header)
  /// @param mass_kg  the calibration's mass m0 when the thrust scale s is estimated: mass.csv
  /// then holds s and the mass it implies, m = m0 / s (docs/notes/mass-state.md)
  /// @param time_offset  the time offset is estimated: time_offset.csv (t, t_d [s], sigma [s])
  RunOutputs(const std::filesystem::path& out_dir, bool write_force, std::optional<double> mass_kg = std::nullopt,
             bool time_offset = false);
  void write_estimate(const EstimateRow& row);
  /// @brief A pose without a filter state (trajectory_tum.txt only): the in-flight
  /// initializer's window after a re-initialization.
  void write_pose(const TimedPose& pose);
  void write_timing(const TimingRow& row);
  /// @brief A comment line in trajectory_tum.txt before the first estimate after a
  /// re-initialization (docs/notes/recovery.md): from @p t_ns on, a new world frame.
  void mark_reinitialization(TimeNs t_ns);
  void close();

 private:
  bool write_force_;
  std::optional<double> mass_kg_;
  FlushedFile tum_, state_, force_, timing_;
  std::optional<FlushedFile> mass_;
  std::optional<FlushedFile> time_offset_;
};

/// @brief trajectory_smoothed_tum.txt and force_smoothed.csv (fixed-lag smoothed estimates,
/// docs/notes/smoothing.md): the formats of trajectory_tum.txt and force.csv.
class SmoothedOutputs {
 public:
  explicit SmoothedOutputs(const std::filesystem::path& out_dir);
  void write_estimate(const EstimateRow& row);
  /// @brief As RunOutputs::mark_reinitialization, in trajectory_smoothed_tum.txt.
  void mark_reinitialization(TimeNs t_ns);
  void close();

 private:
  FlushedFile tum_, force_;
};

/// @brief One line of force.csv (and force_smoothed.csv) for @p row.
std::string force_csv_line(const EstimateRow& row);

/// @brief Header line of state.csv (shared with the Python loader, vid_eval.formats).
std::string state_csv_header();
/// @brief Header line of force.csv.
std::string force_csv_header();
/// @brief Header line of mass.csv.
std::string mass_csv_header();
/// @brief One line of mass.csv: m = m0 / s and sigma_m = m0 sigma_s / s^2 (the thrust scale s
/// with the calibration's mass m0).
std::string mass_csv_line(const EstimateRow& row, double mass_kg);
/// @brief Header line of timing.csv.
std::string timing_csv_header();
/// @brief Header line of tracks.csv (vid_track's output, vid_eval.formats.TRACKS_COLUMNS).
std::string tracks_csv_header();
/// @brief One row of tracks.csv: time, camera, feature id, distorted pixel u, v.
std::string tracks_csv_row(TimeNs t_ns, const FeatureObservation& ob);

}  // namespace vid::system
