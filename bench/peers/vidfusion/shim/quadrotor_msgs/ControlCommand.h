// Part of the ROS-free shim for building VID-Fusion (GPL-3) without ROS: bench/peers/vidfusion.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Written for VID-MSCKF; compiled only into vidfusion_driver, which links VID-Fusion (GPL-3),
// so it is GPL-3.0-or-later like the driver (bench/peers/README.md). It is not ROS code: it
// provides only the names VID-Fusion's estimator and feature-tracker sources use.
#pragma once
// The control input their node reads: collective_thrust = mass-normalised collective thrust
// [m/s^2] along body z (their dynamic_model node: sum_i k_i w_i^2 / mass).
#include <memory>
#include "std_msgs/Header.h"
namespace quadrotor_msgs {
struct ControlCommand {
  std_msgs::Header header;
  double collective_thrust = 0;
  using ConstPtr = std::shared_ptr<const ControlCommand>;
};
}  // namespace quadrotor_msgs
