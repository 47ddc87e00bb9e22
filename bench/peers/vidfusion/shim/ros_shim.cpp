// Part of the ROS-free shim for building VID-Fusion (GPL-3) without ROS: bench/peers/vidfusion.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Written for VID-MSCKF; compiled only into vidfusion_driver, which links VID-Fusion (GPL-3),
// so it is GPL-3.0-or-later like the driver (bench/peers/README.md). It is not ROS code: it
// provides only the names VID-Fusion's estimator and feature-tracker sources use.
#include <chrono>
#include <cstdarg>
#include <cstdio>

#include "ros/ros.h"

namespace ros {
namespace console {
int g_level = 1;
static const char *kName[] = {"DEBUG", "INFO", "WARN", "ERROR", "FATAL"};
void print(int level, const char *fmt, ...) {
  std::fprintf(stderr, "[vidfusion %s] ", kName[level < 0 ? 0 : (level > 4 ? 4 : level)]);
  va_list ap;
  va_start(ap, fmt);
  std::vfprintf(stderr, fmt, ap);
  va_end(ap);
  std::fputc('\n', stderr);
}
void print_str(int level, const std::string &s) { print(level, "%s", s.c_str()); }
}  // namespace console

Time Time::now() {
  using namespace std::chrono;
  return Time(duration<double>(system_clock::now().time_since_epoch()).count());
}
}  // namespace ros
