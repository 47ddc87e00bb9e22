// Part of the ROS-free shim for building VID-Fusion (GPL-3) without ROS: bench/peers/vidfusion.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Written for VID-MSCKF; compiled only into vidfusion_driver, which links VID-Fusion (GPL-3),
// so it is GPL-3.0-or-later like the driver (bench/peers/README.md). It is not ROS code: it
// provides only the names VID-Fusion's estimator and feature-tracker sources use.
#pragma once
#include <cstdio>
#include <sstream>
#include <string>

namespace ros {
namespace console {
// 0 debug, 1 info, 2 warn, 3 error, 4 fatal, 5 silent. ROS's default is info; the driver sets
// it (--log-level). Arguments of a disabled level are not evaluated, as in ROS.
extern int g_level;
void print(int level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void print_str(int level, const std::string &s);
}  // namespace console
}  // namespace ros

#define VF_SHIM_LOG(lvl, ...) \
  do { if ((lvl) >= ::ros::console::g_level) ::ros::console::print((lvl), __VA_ARGS__); } while (0)
#define VF_SHIM_LOG_STREAM(lvl, args) \
  do { if ((lvl) >= ::ros::console::g_level) { std::ostringstream vf_ss_; vf_ss_ << args; \
       ::ros::console::print_str((lvl), vf_ss_.str()); } } while (0)

#define ROS_DEBUG(...) VF_SHIM_LOG(0, __VA_ARGS__)
#define ROS_INFO(...) VF_SHIM_LOG(1, __VA_ARGS__)
#define ROS_WARN(...) VF_SHIM_LOG(2, __VA_ARGS__)
#define ROS_ERROR(...) VF_SHIM_LOG(3, __VA_ARGS__)
#define ROS_FATAL(...) VF_SHIM_LOG(4, __VA_ARGS__)
#define ROS_DEBUG_STREAM(args) VF_SHIM_LOG_STREAM(0, args)
#define ROS_INFO_STREAM(args) VF_SHIM_LOG_STREAM(1, args)
#define ROS_WARN_STREAM(args) VF_SHIM_LOG_STREAM(2, args)
#define ROS_ERROR_STREAM(args) VF_SHIM_LOG_STREAM(3, args)
#define ROS_FATAL_STREAM(args) VF_SHIM_LOG_STREAM(4, args)
#define ROS_DEBUG_STREAM_ONCE(args) \
  do { static bool vf_once_ = false; if (!vf_once_) { vf_once_ = true; ROS_DEBUG_STREAM(args); } } while (0)
#define ROS_INFO_ONCE(...) \
  do { static bool vf_once_ = false; if (!vf_once_) { vf_once_ = true; ROS_INFO(__VA_ARGS__); } } while (0)
#define ROS_WARN_ONCE(...) \
  do { static bool vf_once_ = false; if (!vf_once_) { vf_once_ = true; ROS_WARN(__VA_ARGS__); } } while (0)
