#include "vid_system/summary.h"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>

namespace vid::system {

void StageTimes::add(const TimingRow& r) {
  tracking_.add(r.tracking_ms);
  propagation_.add(r.propagation_ms);
  accel_.add(r.accel_update_ms);
  msckf_.add(r.msckf_update_ms);
  marginalization_.add(r.marginalization_ms);
  total_.add(r.total_ms);
}

nlohmann::json StageTimes::to_json() const {
  nlohmann::json j;
  j["tracking"] = tracking_.to_json();
  j["propagation"] = propagation_.to_json();
  j["accel_updates"] = accel_.to_json();
  j["msckf_update"] = msckf_.to_json();
  j["marginalization"] = marginalization_.to_json();
  j["total"] = total_.to_json();
  return j;
}

double peak_memory_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

double process_cpu_s() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto sec = [](const timeval& tv) { return static_cast<double>(tv.tv_sec) + 1e-6 * static_cast<double>(tv.tv_usec); };
  return sec(usage.ru_utime) + sec(usage.ru_stime);
}

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

void write_summary(const std::filesystem::path& out_dir, const nlohmann::json& summary) {
  const auto path = out_dir / "summary.json";
  std::ofstream f(path);
  // Messages quoted from bad input may hold invalid UTF-8: replaced, so the summary is still written.
  f << summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
  f.flush();
  if (!f) throw std::runtime_error(path.string() + ": write failed");
}

}  // namespace vid::system
