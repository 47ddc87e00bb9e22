// Part of the ROS-free shim for building VID-Fusion (GPL-3) without ROS: bench/peers/vidfusion.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Written for VID-MSCKF; compiled only into vidfusion_driver, which links VID-Fusion (GPL-3),
// so it is GPL-3.0-or-later like the driver (bench/peers/README.md). It is not ROS code: it
// provides only the names VID-Fusion's estimator and feature-tracker sources use.
#pragma once
#include <cstdio>
#include <cstdlib>

// As ROS's ros/assert.h: ROS_ASSERT* are compiled out under NDEBUG (Release) unless
// ROS_ASSERT_ENABLED is defined; ROS_BREAK always aborts.
#define ROS_BREAK() \
  do { std::fprintf(stderr, "ROS_BREAK at %s:%d\n", __FILE__, __LINE__); std::abort(); } while (0)
#if defined(NDEBUG) && !defined(ROS_ASSERT_ENABLED)
#define ROS_ASSERT(cond) do { if (false) { (void)(cond); } } while (0)
#define ROS_ASSERT_MSG(cond, ...) do { if (false) { (void)(cond); } } while (0)
#else
#define ROS_ASSERT(cond) \
  do { if (!(cond)) { std::fprintf(stderr, "ASSERTION FAILED %s:%d: %s\n", __FILE__, __LINE__, #cond); \
       std::abort(); } } while (0)
#define ROS_ASSERT_MSG(cond, ...) \
  do { if (!(cond)) { std::fprintf(stderr, "ASSERTION FAILED %s:%d: %s: ", __FILE__, __LINE__, #cond); \
       std::fprintf(stderr, __VA_ARGS__); std::fprintf(stderr, "\n"); std::abort(); } } while (0)
#endif
