#pragma once
/// @file gyro_integrator.h
/// @brief Buffers gyro samples and integrates the body rotation between two times.

#include <Eigen/Core>
#include <deque>
#include <optional>

#include "types/measurements.h"

namespace vid {

/// @brief Gyro buffer with bounded size; rotation between two times by piecewise-linear rates.
class GyroIntegrator {
 public:
  /// @param max_samples  oldest samples are dropped beyond this count (bounded memory)
  explicit GyroIntegrator(std::size_t max_samples = 4000) : max_samples_(max_samples) {}

  /// @brief Add a sample (samples out of time order are ignored).
  void add(const ImuSample& s);
  /// @brief R_{I(t0) I(t1)}: orientation of the IMU at t1 in the IMU frame at t0. Rates are
  /// interpolated linearly between samples and held beyond the buffer's ends. nullopt if the
  /// buffer holds no sample within `max_gap_ns` of [t0, t1].
  std::optional<Eigen::Matrix3d> rotation(TimeNs t0, TimeNs t1,
                                          TimeNs max_gap_ns = 50'000'000) const;
  /// @brief Drop samples not needed for intervals starting at or after t.
  void prune_before(TimeNs t);
  /// @brief Number of buffered samples.
  std::size_t size() const { return buf_.size(); }

 private:
  Eigen::Vector3d rate_at(TimeNs t) const;
  std::size_t max_samples_;
  std::deque<ImuSample> buf_;
};

}  // namespace vid
