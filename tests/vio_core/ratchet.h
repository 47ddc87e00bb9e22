#pragma once
// Ratchet checks (docs/testing.md): a figure not yet at its target is held at today's measured
// value plus a margin from its spread over seeds; the test prints the value so that an
// improvement is seen (and the ratchet tightened).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace vid::test {

/// @brief EXPECT value <= limit (lower is better); prints the value, the ratchet and the value
/// measured when the ratchet was set, and asks for tightening once value beats it by the margin.
inline void expect_ratchet(const char* what, double value, double limit, double measured) {
  std::printf("[ratchet] %s: %.4g (ratchet %.4g, measured %.4g when set)\n", what, value, limit, measured);
  if (measured - value > limit - measured)
    std::printf("[ratchet] %s improved past its margin: tighten the ratchet (docs/testing.md)\n", what);
  EXPECT_LE(value, limit) << what << " regressed (measured " << measured << " when the ratchet was set)";
}

/// @brief EXPECT value >= limit (higher is better, e.g. a fraction of time inside a band).
inline void expect_ratchet_at_least(const char* what, double value, double limit, double measured) {
  std::printf("[ratchet] %s: %.4g (ratchet >= %.4g, measured %.4g when set)\n", what, value, limit, measured);
  if (value - measured > measured - limit)
    std::printf("[ratchet] %s improved past its margin: tighten the ratchet (docs/testing.md)\n", what);
  EXPECT_GE(value, limit) << what << " regressed (measured " << measured << " when the ratchet was set)";
}

/// @brief EXPECT lo <= value <= hi (two-sided: a consistency figure fails in either direction).
inline void expect_in_band(const char* what, double value, double lo, double hi) {
  std::printf("[ratchet] %s: %.4g (band [%.4g, %.4g])\n", what, value, lo, hi);
  EXPECT_GE(value, lo) << what;
  EXPECT_LE(value, hi) << what;
}

}  // namespace vid::test

namespace vid::test {

/// @brief The C++ form of a strict xfail (docs/testing.md): EXPECT the figure to still miss its
/// target (value > target, lower is better), so that the day it is met this fails and asks for
/// the target to become a plain check. Setup checks stay outside, as ordinary EXPECTs.
inline void expect_target_not_met(const char* what, double value, double target) {
  std::printf("[target] %s: %.4g (target <= %.4g, not met yet)\n", what, value, target);
  EXPECT_GT(value, target) << what << " meets its target now: make it a plain EXPECT_LE and drop its ratchet";
}

/// @brief expect_target_not_met for a figure where higher is better (a fraction inside a band):
/// EXPECT value < target.
inline void expect_target_not_met_at_least(const char* what, double value, double target) {
  std::printf("[target] %s: %.4g (target >= %.4g, not met yet)\n", what, value, target);
  EXPECT_LT(value, target) << what << " meets its target now: make it a plain EXPECT_GE and drop its ratchet";
}

}  // namespace vid::test
