// Part of the ROS-free shim for building VID-Fusion (GPL-3) without ROS: bench/peers/vidfusion.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Written for VID-MSCKF; compiled only into vidfusion_driver, which links VID-Fusion (GPL-3),
// so it is GPL-3.0-or-later like the driver (bench/peers/README.md). It is not ROS code: it
// provides only the names VID-Fusion's estimator and feature-tracker sources use.
#pragma once
// Included by their estimator.h, not used by the estimator itself (only by its ROS publishers,
// which are not built).
#include "std_msgs/Header.h"
namespace nav_msgs {
struct Odometry {
  std_msgs::Header header;
};
}  // namespace nav_msgs
