#pragma once
/// @file render_internal.h
/// @brief Helpers shared by renderer.cpp and camera_effects.cpp (not public API).

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace vid::sim::detail {

/// Inverse standard-normal CDF at 65536 equally likely levels: 16 random bits -> one
/// Gaussian sample by lookup (exact to the table's quantization, far below 1 gray level).
inline const std::array<float, 65536>& normal_table() {
  static const std::array<float, 65536> table = [] {
    std::array<float, 65536> t{};
    for (int i = 0; i < 65536; ++i) {
      const double p = (i + 0.5) / 65536.0;
      double x = 0.0;
      for (int it = 0; it < 60; ++it) {  // Newton on Phi(x) - p
        const double cdf = 0.5 * std::erfc(-x / std::numbers::sqrt2);
        const double pdf = std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
        const double step = (cdf - p) / std::max(pdf, 1e-300);
        x -= std::clamp(step, -1.0, 1.0);
        if (std::abs(step) < 1e-13) break;
      }
      t[i] = static_cast<float>(x);
    }
    return t;
  }();
  return table;
}

}  // namespace vid::sim::detail
