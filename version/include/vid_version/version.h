#pragma once
/// @file version.h
/// @brief The project version and the git commit the build came from.

#include <string>

namespace vid {

/// @brief Project version (CMake project(), e.g. "0.1.0").
const char* version();
/// @brief git commit of the build (12 hex digits; "-dirty" with uncommitted changes, "unknown"
/// outside a git checkout).
const char* git_sha();
/// @brief What --version prints: "PROGRAM 0.1.0 (git 0123456789ab)".
inline std::string version_line(const std::string& program) {
  return program + " " + version() + " (git " + git_sha() + ")";
}

}  // namespace vid
