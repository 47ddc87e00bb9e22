#include "vid_system/stage_stats.h"

#include <algorithm>
#include <cmath>

namespace vid::system {

namespace {
// Buckets cover [kLow, kLow * gamma^kBuckets) ms: 1 ns to ~3 h; values at or below kLow share
// bucket 0, values above the range the last bucket (quantiles are clamped to [min, max]).
constexpr double kLow = 1e-6;
const double kGamma = (1.0 + StageStats::kRelativeError) / (1.0 - StageStats::kRelativeError);
const double kLogGamma = std::log(kGamma);
const std::size_t kBuckets = static_cast<std::size_t>(std::ceil(std::log(1e10 / kLow) / kLogGamma)) + 1;
}  // namespace

std::size_t StageStats::bucket(double ms) const {
  if (!(ms > kLow)) return 0;
  const double k = std::ceil(std::log(ms / kLow) / kLogGamma);
  return std::min(kBuckets - 1, static_cast<std::size_t>(k));
}

double StageStats::bucket_value(std::size_t b) const {
  // Values in bucket b lie in (kLow gamma^(b-1), kLow gamma^b]; this point is within
  // kRelativeError of each of them.
  return b == 0 ? kLow : kLow * std::pow(kGamma, static_cast<double>(b)) * 2.0 / (1.0 + kGamma);
}

void StageStats::to_histogram() {
  buckets_.assign(kBuckets, 0);
  for (double v : exact_) ++buckets_[bucket(v)];
  std::vector<double>().swap(exact_);  // release the memory
}

void StageStats::add(double ms) {
  min_ = count_ == 0 ? ms : std::min(min_, ms);
  max_ = count_ == 0 ? ms : std::max(max_, ms);
  sum_ += ms;
  ++count_;
  if (buckets_.empty()) {
    exact_.push_back(ms);
    if (exact_.size() > kExactSamples) to_histogram();
  } else {
    ++buckets_[bucket(ms)];
  }
}

double StageStats::quantile(double q) const {
  if (count_ == 0) return 0.0;
  const auto rank = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(q * static_cast<double>(count_))));
  if (buckets_.empty()) {
    std::vector<double> v = exact_;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(std::min(rank, v.size()) - 1), v.end());
    return v[std::min(rank, v.size()) - 1];
  }
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < buckets_.size(); ++b) {
    seen += buckets_[b];
    if (seen >= rank) return b == 0 ? min_ : std::clamp(bucket_value(b), min_, max_);  // bucket 0: <= 1 ns
  }
  return max_;
}

nlohmann::json StageStats::to_json() const {
  nlohmann::json j;
  j["count"] = count_;
  if (count_ == 0) return j;
  j["mean_ms"] = sum_ / static_cast<double>(count_);
  j["median_ms"] = quantile(0.5);
  j["p99_ms"] = quantile(0.99);
  j["max_ms"] = max_;
  return j;
}

nlohmann::json stage_stats(const std::vector<double>& values) {
  StageStats s;
  for (double v : values) s.add(v);
  return s.to_json();
}

}  // namespace vid::system
