#pragma once
/// @file number_format.h
/// @brief Number formatting that round-trips exactly (shortest representation that parses
/// back to the same double), used by every file the io module writes.

#include <string>
#include <vector>

namespace vid::io {

/// @brief Shortest decimal text that parses back to exactly @p v (e.g. "0.1", "1e-07").
std::string format_double(double v);

/// @brief "[a, b, c]" with format_double for each element (YAML flow sequence).
std::string format_list(const std::vector<double>& v);

}  // namespace vid::io
