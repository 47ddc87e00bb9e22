#pragma once
/// @file feature_database.h
/// @brief Feature tracks accumulated from FeatureFrames, and the MSCKF selection of tracks
/// to use in a visual update (lost tracks, and tracks seen by the clone about to be
/// marginalized).

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "types/measurements.h"
#include "vio_core/msckf/msckf_types.h"

namespace vid::msckf {

/// @brief Tracks by feature id. Memory is bounded: tracks not observed for
/// max_track_age_ns and observations older than the oldest clone are dropped.
class FeatureDatabase {
 public:
  /// @brief max_track_age_ns: tracks whose newest observation is older than this (relative
  /// to the newest frame added) are dropped; max_tracks: hard cap (oldest tracks dropped).
  explicit FeatureDatabase(TimeNs max_track_age_ns = 5'000'000'000LL,
                           std::size_t max_tracks = 20000);

  /// @brief Add all observations of a frame (uses uv_norm). Throws std::invalid_argument
  /// if an observation has has_norm == false or the frame is older than a previous one.
  void add(const FeatureFrame& frame);

  /// @brief Tracks for the visual update, removed from the database:
  /// tracks not observed at newest_t (lost) and, when window_full, tracks observed at the
  /// oldest clone time. Returned tracks contain only observations at clone times; tracks with
  /// no such observation are dropped silently. Observations older than the oldest clone are
  /// pruned from the remaining tracks.
  std::vector<FeatureTrack> select_for_update(const std::vector<ClonePose>& clones,
                                              TimeNs newest_t, bool window_full);

  /// @brief Remove every observation at time t (the clone at t is being marginalized).
  void remove_observations_at(TimeNs t);

  /// @brief Number of tracks held.
  std::size_t num_tracks() const { return tracks_.size(); }
  /// @brief Number of observations held over all tracks.
  std::size_t num_observations() const;
  /// @brief Tracks dropped because they went stale or exceeded the cap (cumulative).
  std::size_t num_dropped() const { return dropped_; }
  /// @brief Observations rejected by add() as duplicates of (feature, time, cam) (cumulative).
  std::size_t num_duplicates() const { return duplicates_; }

 private:
  void drop_stale(TimeNs newest_t);

  TimeNs max_track_age_ns_;
  std::size_t max_tracks_;
  TimeNs newest_added_ = INT64_MIN;
  std::unordered_map<std::uint64_t, FeatureTrack> tracks_;
  std::size_t dropped_ = 0;
  std::size_t duplicates_ = 0;
};

}  // namespace vid::msckf
