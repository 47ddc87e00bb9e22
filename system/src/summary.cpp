#include "vid_system/summary.h"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>

namespace vid::system {

nlohmann::json stage_stats(std::vector<double> v) {
  nlohmann::json j;
  if (v.empty()) {
    j["count"] = 0;
    return j;
  }
  std::sort(v.begin(), v.end());
  const auto quantile = [&v](double q) {
    // Nearest-rank quantile: the smallest value with at least q of the sample at or below it.
    const std::size_t rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
  };
  j["count"] = v.size();
  j["mean_ms"] = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  j["median_ms"] = quantile(0.5);
  j["p99_ms"] = quantile(0.99);
  j["max_ms"] = v.back();
  return j;
}

void StageTimes::add(const TimingRow& r) {
  tracking_.push_back(r.tracking_ms);
  propagation_.push_back(r.propagation_ms);
  accel_.push_back(r.accel_update_ms);
  msckf_.push_back(r.msckf_update_ms);
  marginalization_.push_back(r.marginalization_ms);
  total_.push_back(r.total_ms);
}

nlohmann::json StageTimes::to_json() const {
  nlohmann::json j;
  j["tracking"] = stage_stats(tracking_);
  j["propagation"] = stage_stats(propagation_);
  j["accel_updates"] = stage_stats(accel_);
  j["msckf_update"] = stage_stats(msckf_);
  j["marginalization"] = stage_stats(marginalization_);
  j["total"] = stage_stats(total_);
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
