#pragma once
/// @file stage_stats.h
/// @brief Summary statistics of per-frame times in bounded memory (summary.json "timing").

#include <cstddef>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

namespace vid::system {

/// @brief Count, mean, nearest-rank median / p99 and max of a stream of times [ms], in memory
/// that does not grow with the run: the first kExactSamples values are kept and their
/// statistics are exact; past that they move into a log-spaced histogram whose quantiles are
/// within kRelativeError of the exact ones (count, mean and max stay exact). A one-hour live
/// run (108k frames, ten statistics) would otherwise hold ~10 MB of samples. Written here
/// because no Debian-packaged C++ quantile sketch exists; the scheme is DDSketch's
/// (Masson et al., VLDB 2019) with a fixed range.
class StageStats {
 public:
  static constexpr std::size_t kExactSamples = 4096;
  static constexpr double kRelativeError = 0.005;

  void add(double ms);
  std::size_t count() const { return count_; }
  /// @brief {"count", "mean_ms", "median_ms", "p99_ms", "max_ms"} ({"count": 0} when empty).
  nlohmann::json to_json() const;
  /// @brief Nearest-rank quantile: the smallest value with at least q of the sample at or below.
  double quantile(double q) const;

 private:
  void to_histogram();
  std::size_t bucket(double ms) const;
  double bucket_value(std::size_t b) const;

  std::size_t count_ = 0;
  double sum_ = 0.0, min_ = 0.0, max_ = 0.0;
  std::vector<double> exact_;          ///< all samples while count_ <= kExactSamples
  std::vector<std::uint64_t> buckets_;  ///< histogram once past kExactSamples (empty before)
};

/// @brief Statistics of a finished sample (tests, one-off use).
nlohmann::json stage_stats(const std::vector<double>& values);

}  // namespace vid::system
