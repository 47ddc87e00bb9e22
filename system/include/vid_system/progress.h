#pragma once
/// @file progress.h
/// @brief A one-line progress bar on stderr, shown only when stderr is a terminal and CI is unset.

#include <chrono>
#include <string>

namespace vid::system {

/// @brief Terminal progress bar: fraction, rate, ETA and a caller-supplied extra text.
class ProgressBar {
 public:
  /// @param label  short name shown at the left
  /// @param total  amount of work (any unit: frames, seconds of data)
  ProgressBar(std::string label, double total);
  ~ProgressBar();
  /// @brief Report progress; redraws at most ~10 times per second.
  void update(double done, const std::string& extra = "");
  /// @brief Draw the final state and end the line.
  void finish(const std::string& extra = "");
  /// @brief True when the bar is drawn (stderr is a tty and CI is not set).
  bool enabled() const { return enabled_; }

 private:
  std::string label_;
  double total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  void draw(double done, const std::string& extra);
};

}  // namespace vid::system
