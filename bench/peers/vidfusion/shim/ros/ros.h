// Part of the ROS-free shim for building VID-Fusion (GPL-3) without ROS: bench/peers/vidfusion.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Written for VID-MSCKF; compiled only into vidfusion_driver, which links VID-Fusion (GPL-3),
// so it is GPL-3.0-or-later like the driver (bench/peers/README.md). It is not ROS code: it
// provides only the names VID-Fusion's estimator and feature-tracker sources use.
#pragma once
// ROS's ros/ros.h brings in <iostream> and more; their sources rely on it (std::cerr).
#include <cstdint>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "ros/assert.h"
#include "ros/console.h"

namespace ros {

struct Duration {
  double sec_ = 0;
  Duration() = default;
  explicit Duration(double s) : sec_(s) {}
  double toSec() const { return sec_; }
};

// Seconds as a double (their sources only call toSec() on header stamps).
struct Time {
  double sec_ = 0;
  Time() = default;
  explicit Time(double s) : sec_(s) {}
  double toSec() const { return sec_; }
  Time &fromSec(double s) { sec_ = s; return *this; }
  static Time now();
  Duration operator-(const Time &o) const { return Duration(sec_ - o.sec_); }
  bool operator<(const Time &o) const { return sec_ < o.sec_; }
  bool operator==(const Time &o) const { return sec_ == o.sec_; }
};

// The parameter server of a node: the driver fills it (set) before calling their
// readParameters(n), which reads "config_file" (and "vins_folder") from it.
class NodeHandle {
 public:
  explicit NodeHandle(const std::string &ns = "") : ns_(ns) {}
  static void set(const std::string &name, const std::string &value) { params()[name] = value; }
  bool getParam(const std::string &name, std::string &out) const {
    auto it = params().find(name);
    if (it == params().end()) return false;
    out = it->second;
    return true;
  }
  template <typename T> bool getParam(const std::string &name, T &out) const {
    std::string s;
    if (!getParam(name, s)) return false;
    std::istringstream is(s);
    is >> out;
    return !is.fail();
  }
  void shutdown() {}

 private:
  static std::map<std::string, std::string> &params() {
    static std::map<std::string, std::string> p;
    return p;
  }
  std::string ns_;
};

}  // namespace ros
