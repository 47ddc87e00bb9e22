#pragma once
/// @file reorder_window.h
/// @brief Puts live messages back into timestamp order. A message is held until the newest
/// timestamp seen on any stream is `window` past it, then released in (time, stream) order.
/// Duplicates and messages at or before the release point (the last released (time, stream)
/// of any stream) are dropped as late, so the estimator always gets its input in time order;
/// messages that arrive after a later one are accepted (reordered); gaps in a stream are
/// counted as missing messages (the period of each stream is learnt from its smallest interval).

#include <array>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <vector>

#include "live/live_types.h"

namespace vid::live {

/// @brief Bounded reorder window with fault classification. Not thread-safe.
class ReorderWindow {
 public:
  /// @param window_ns  how long (data time) a message is held for late-comers
  explicit ReorderWindow(TimeNs window_ns);

  /// @brief Offer a decoded message. Returns false when it is dropped (duplicate or late).
  bool insert(LiveItem item);
  /// @brief Messages whose time is at least the window behind the newest one, in order.
  std::vector<LiveItem> pop_ready();
  /// @brief Every held message, in order (end of stream).
  std::vector<LiveItem> flush();

  /// @brief Count a payload that could not be decoded on stream @p s.
  void count_malformed(Stream s) { counters_[static_cast<int>(s)].malformed++; }
  const StreamCounters& counters(Stream s) const { return counters_[static_cast<int>(s)]; }
  std::size_t held() const { return held_.size(); }
  TimeNs newest() const { return newest_; }

 private:
  using Key = std::tuple<TimeNs, int>;  // (time, stream); one message per key
  void on_release(const LiveItem& item);

  TimeNs window_ns_;
  TimeNs newest_ = INT64_MIN;
  std::map<Key, LiveItem> held_;
  std::array<StreamCounters, kNumStreams> counters_{};
  std::array<TimeNs, kNumStreams> released_{};     ///< last released time per stream
  std::array<bool, kNumStreams> any_released_{};
  std::optional<Key> last_released_;               ///< release point over all streams
  std::array<TimeNs, kNumStreams> period_{};       ///< smallest interval seen (0: unknown)
  std::array<std::set<TimeNs>, kNumStreams> recent_;  ///< recently released times (duplicate check)
};

}  // namespace vid::live
