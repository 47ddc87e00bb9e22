#pragma once
/// @file time.h
/// @brief The one time type of files and interfaces (integer nanoseconds) and its conversions
/// to and from seconds.

#include <cmath>
#include <cstdint>

namespace vid {

/// Nanoseconds since an arbitrary epoch; the only time type in files and interfaces.
using TimeNs = std::int64_t;

/// @brief Convert nanoseconds to seconds (double).
inline double ns_to_s(TimeNs t) { return static_cast<double>(t) * 1e-9; }
/// @brief Convert seconds to nanoseconds (rounded to the nearest).
inline TimeNs seconds_to_ns(double s) { return static_cast<TimeNs>(std::llround(s * 1e9)); }

}  // namespace vid
