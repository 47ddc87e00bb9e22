// Part of the ROS-free shim for building VID-Fusion (GPL-3) without ROS: bench/peers/vidfusion.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Written for VID-MSCKF; compiled only into vidfusion_driver, which links VID-Fusion (GPL-3),
// so it is GPL-3.0-or-later like the driver (bench/peers/README.md). It is not ROS code: it
// provides only the names VID-Fusion's estimator and feature-tracker sources use.
#pragma once
namespace std_msgs {
struct Float32 {
  float data = 0;
};
}  // namespace std_msgs
