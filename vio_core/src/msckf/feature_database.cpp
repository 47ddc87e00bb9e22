/// @file feature_database.cpp
/// @brief Feature tracks and the MSCKF selection logic (lost tracks, tracks of the clone about
/// to be marginalized).

#include "vio_core/msckf/feature_database.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace vid::msckf {

FeatureDatabase::FeatureDatabase(TimeNs max_track_age_ns, std::size_t max_tracks)
    : max_track_age_ns_(max_track_age_ns), max_tracks_(max_tracks) {
  if (max_track_age_ns <= 0 || max_tracks == 0) {
    throw std::invalid_argument(std::string(__FILE__) +
                                ": FeatureDatabase: max_track_age_ns and max_tracks must be > 0");
  }
}

void FeatureDatabase::add(const FeatureFrame& frame) {
  if (frame.t_ns < newest_added_) {
    throw std::invalid_argument(std::string(__FILE__) + ": FeatureDatabase::add: frame at " +
                                std::to_string(frame.t_ns) + " ns is older than the newest (" +
                                std::to_string(newest_added_) + " ns)");
  }
  for (const FeatureObservation& o : frame.observations) {
    if (!o.has_norm) {
      throw std::invalid_argument(std::string(__FILE__) + ": FeatureDatabase::add: feature " +
                                  std::to_string(o.feature_id) + " cam " +
                                  std::to_string(o.cam_id) + " at " +
                                  std::to_string(frame.t_ns) +
                                  " ns has no undistorted coordinates (has_norm = false)");
    }
  }
  newest_added_ = frame.t_ns;
  for (const FeatureObservation& o : frame.observations) {
    FeatureTrack& tr = tracks_[o.feature_id];
    tr.feature_id = o.feature_id;
    const bool dup = std::any_of(tr.obs.rbegin(), tr.obs.rend(), [&](const TrackObservation& x) {
      return x.t_ns == frame.t_ns && x.cam_id == o.cam_id;
    });
    if (dup) {
      ++duplicates_;
      continue;
    }
    tr.obs.push_back({frame.t_ns, o.cam_id, o.uv_norm});
    // Keep (t, cam) order; frames arrive in time order, so only cams may need sorting.
    for (std::size_t i = tr.obs.size() - 1; i > 0; --i) {
      TrackObservation& a = tr.obs[i - 1];
      TrackObservation& b = tr.obs[i];
      if (a.t_ns == b.t_ns && a.cam_id > b.cam_id) {
        std::swap(a, b);
      } else {
        break;
      }
    }
  }
  drop_stale(frame.t_ns);
}

void FeatureDatabase::drop_stale(TimeNs newest_t) {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    if (it->second.obs.empty() || newest_t - it->second.obs.back().t_ns > max_track_age_ns_) {
      it = tracks_.erase(it);
      ++dropped_;
    } else {
      ++it;
    }
  }
  if (tracks_.size() <= max_tracks_) return;
  // Over the cap: drop the tracks last seen longest ago.
  std::vector<std::pair<TimeNs, std::uint64_t>> last_seen;
  last_seen.reserve(tracks_.size());
  for (const auto& [id, tr] : tracks_) last_seen.emplace_back(tr.obs.back().t_ns, id);
  const std::size_t excess = tracks_.size() - max_tracks_;
  std::nth_element(last_seen.begin(), last_seen.begin() + static_cast<std::ptrdiff_t>(excess),
                   last_seen.end());
  for (std::size_t i = 0; i < excess; ++i) tracks_.erase(last_seen[i].second);
  dropped_ += excess;
}

std::vector<FeatureTrack> FeatureDatabase::select_for_update(const std::vector<ClonePose>& clones,
                                                             TimeNs newest_t, bool window_full) {
  std::vector<FeatureTrack> out;
  if (clones.empty()) return out;
  std::unordered_set<TimeNs> clone_times;
  TimeNs oldest = clones.front().t_ns;
  for (const ClonePose& c : clones) {
    clone_times.insert(c.t_ns);
    oldest = std::min(oldest, c.t_ns);
  }
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    FeatureTrack& tr = it->second;
    bool seen_newest = false;
    bool seen_oldest = false;
    for (const TrackObservation& o : tr.obs) {
      seen_newest |= (o.t_ns == newest_t);
      seen_oldest |= (o.t_ns == oldest);
    }
    if (!seen_newest || (window_full && seen_oldest)) {
      FeatureTrack sel;
      sel.feature_id = tr.feature_id;
      for (const TrackObservation& o : tr.obs) {
        if (clone_times.count(o.t_ns) != 0) sel.obs.push_back(o);
      }
      if (!sel.obs.empty()) out.push_back(std::move(sel));
      it = tracks_.erase(it);
      continue;
    }
    // Observations older than the window can never be used again.
    std::erase_if(tr.obs, [&](const TrackObservation& o) { return o.t_ns < oldest; });
    if (tr.obs.empty()) {
      it = tracks_.erase(it);
    } else {
      ++it;
    }
  }
  // Deterministic order regardless of hash-map iteration.
  std::sort(out.begin(), out.end(), [](const FeatureTrack& a, const FeatureTrack& b) {
    return a.feature_id < b.feature_id;
  });
  return out;
}

void FeatureDatabase::remove_observations_at(TimeNs t) {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    std::erase_if(it->second.obs, [t](const TrackObservation& o) { return o.t_ns == t; });
    if (it->second.obs.empty()) {
      it = tracks_.erase(it);
    } else {
      ++it;
    }
  }
}

std::size_t FeatureDatabase::num_observations() const {
  std::size_t n = 0;
  for (const auto& [id, tr] : tracks_) n += tr.obs.size();
  return n;
}

}  // namespace vid::msckf
