#pragma once
/// @file force_check.h
/// @brief The run's mean estimated external force, checked against 2 g: an accelerometer whose
/// sign or frame is flipped against the thrust (z down where the thrust is taken along +z, z up)
/// leaves the filter explaining gravity twice with an external force of about 2 g.

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace vid::system {

/// @brief Running mean of |F_ext| over a run's estimates (the norm is the same in body and world).
class ForceMagnitude {
 public:
  /// @brief One estimate's external force (mass-normalized, m/s^2, any frame).
  void add(const Eigen::Vector3d& F) {
    sum_ += F.norm();
    ++n_;
  }
  long samples() const { return n_; }
  /// @brief Mean |F_ext| [m/s^2] (0 without samples).
  double mean_mps2() const { return n_ > 0 ? sum_ / static_cast<double>(n_) : 0.0; }

 private:
  double sum_ = 0.0;
  long n_ = 0;
};

/// @brief Mean |F_ext| above this many g over a run is warned about (flipped sign or frame).
inline constexpr double kForceNear2gThreshold = 1.5;

/// @brief Add summary.json's `force_check` (mean |F_ext| in m/s^2 and g, the threshold) and, when
/// the mean is above kForceNear2gThreshold g, the named warning `external_force_near_2g: ...` to
/// the top-level `warnings` list of @p s. Nothing without samples (imu mode).
void add_force_check(nlohmann::json& s, const ForceMagnitude& f, double gravity);

}  // namespace vid::system
