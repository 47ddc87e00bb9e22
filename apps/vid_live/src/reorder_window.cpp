#include "live/reorder_window.h"

#include <cmath>

namespace vid::live {

std::string stream_name(Stream s) {
  switch (s) {
    case Stream::kImu: return "imu";
    case Stream::kRotor: return "rotors";
    case Stream::kThrust: return "thrust";
    case Stream::kCam0: return "cam0";
    case Stream::kCam1: return "cam1";
  }
  return "unknown";
}

ReorderWindow::ReorderWindow(TimeNs window_ns) : window_ns_(window_ns) {}

bool ReorderWindow::insert(LiveItem item) {
  const int s = static_cast<int>(item.stream);
  StreamCounters& c = counters_[s];
  const Key key{item.t_ns, s};
  if (held_.count(key) || recent_[s].count(item.t_ns)) {
    ++c.duplicate;
    return false;
  }
  if (last_released_ && key <= *last_released_) {
    // Its place in time has been processed already (by any stream: e.g. the last image before
    // a camera stall, sent late, is behind the IMU that kept flowing).
    ++c.late;
    return false;
  }
  ++c.received;
  if (item.t_ns < newest_) ++c.reordered;
  newest_ = std::max(newest_, item.t_ns);
  held_.emplace(key, std::move(item));
  return true;
}

void ReorderWindow::on_release(const LiveItem& item) {
  const int s = static_cast<int>(item.stream);
  if (any_released_[s]) {
    const TimeNs dt = item.t_ns - released_[s];
    if (dt > 0 && (period_[s] == 0 || dt < period_[s])) period_[s] = dt;
    // A gap of k periods means k - 1 messages never arrived (1.5 periods of tolerance for jitter).
    if (period_[s] > 0 && 2 * dt > 3 * period_[s])
      counters_[s].missing += std::llround(static_cast<double>(dt) / static_cast<double>(period_[s])) - 1;
  }
  released_[s] = item.t_ns;
  any_released_[s] = true;
  last_released_ = Key{item.t_ns, s};
  recent_[s].insert(item.t_ns);
  while (recent_[s].size() > 64) recent_[s].erase(recent_[s].begin());
}

std::vector<LiveItem> ReorderWindow::pop_ready() {
  std::vector<LiveItem> out;
  if (held_.empty()) return out;
  const TimeNs release_to = newest_ - window_ns_;
  while (!held_.empty() && std::get<0>(held_.begin()->first) <= release_to) {
    on_release(held_.begin()->second);
    out.push_back(std::move(held_.begin()->second));
    held_.erase(held_.begin());
  }
  return out;
}

std::vector<LiveItem> ReorderWindow::flush() {
  std::vector<LiveItem> out;
  for (auto& [key, item] : held_) {
    on_release(item);
    out.push_back(std::move(item));
  }
  held_.clear();
  return out;
}

}  // namespace vid::live
