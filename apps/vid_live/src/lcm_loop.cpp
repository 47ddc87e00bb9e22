#include "live/lcm_loop.h"

#include <chrono>
#include <cstdlib>
#include <string_view>

namespace vid::live {

bool is_log_url(const std::string& url) { return url.rfind("file://", 0) == 0; }

bool is_fast_log_url(const std::string& url) {
  if (!is_log_url(url)) return false;
  const auto q = url.find('?');
  if (q == std::string::npos) return false;
  // Query "a=1&speed=0&b=2": look at each key=value pair.
  std::size_t pos = q + 1;
  while (pos <= url.size()) {
    std::size_t amp = url.find('&', pos);
    if (amp == std::string::npos) amp = url.size();
    const std::string_view kv(url.data() + pos, amp - pos);
    if (kv.substr(0, 6) == "speed=") {
      const std::string value(kv.substr(6));
      return !value.empty() && std::strtod(value.c_str(), nullptr) <= 0.0;
    }
    pos = amp + 1;
  }
  return false;
}

std::string run_lcm_loop(lcm::LCM& lcm, const std::string& url, const std::function<bool()>& stop,
                         double idle_timeout_s, const std::atomic<long>& received) {
  using Clock = std::chrono::steady_clock;
  if (is_log_url(url)) {
    // LCM's file provider: handle() returns -1 once the log is exhausted.
    while (!stop())
      if (lcm.handle() < 0) return "eof";
    return "stopped";
  }
  long last_count = received.load();
  auto last_activity = Clock::now();
  while (!stop()) {
    lcm.handleTimeout(100);
    const long n = received.load();
    if (n != last_count) {
      last_count = n;
      last_activity = Clock::now();
    } else if (idle_timeout_s > 0 && n > 0 &&
               std::chrono::duration<double>(Clock::now() - last_activity).count() > idle_timeout_s) {
      return "idle";
    }
  }
  return "stopped";
}

}  // namespace vid::live
