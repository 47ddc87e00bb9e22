#pragma once
/// @file median.h
/// @brief The upper median of a sample, the robust centre used by the rate fit, the parallax
/// test and the IMU stream's period estimate.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace vid {

/// @brief Element v.size() / 2 of v in sorted order (the upper median of an even count);
/// reorders v (std::nth_element, linear time). v must not be empty.
template <typename T>
T upper_median(std::vector<T>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace vid
