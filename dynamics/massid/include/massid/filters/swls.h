#pragma once
/// @file swls.h
/// @brief Sliding-window least squares for the mass (docs/model.md eqs. (57)-(59)) on Ceres:
/// window states [q, p, v, m]_k, pre-integrated dynamic residuals, measurement residuals and
/// a marginalization prior (Schur complement of the dropped state, eq. (57)). Ceres stays
/// private to the library (pimpl).

#include <memory>
#include <vector>

#include "massid/estimator.h"
#include "massid/filters/swls_residuals.h"
#include "massid/filters/tuning.h"

namespace vid::massid {

/// @brief Sliding window over the samples of one run.
class SlidingWindowLs {
 public:
  SlidingWindowLs(const ModelBasedTuning& tuning, const RunInfo& info);
  ~SlidingWindowLs();
  SlidingWindowLs(const SlidingWindowLs&) = delete;
  SlidingWindowLs& operator=(const SlidingWindowLs&) = delete;

  /// @brief Add a sample (input held from the previous sample), slide, solve.
  /// @return the newest state's estimate.
  const QuadMassState& add_sample(const MassIdSample& s);
  /// @brief Current estimates of the window, oldest first.
  std::vector<QuadMassState> window_states() const;
  /// @brief Number of marginalizations done so far.
  int marginalized() const;

  /// @brief The residuals the window would build for a whole run (no marginalization), for
  /// batch comparisons: initial prior, per-interval dynamics and per-sample measurements.
  static void build_residuals(const ModelBasedTuning& tuning, const RunInfo& info,
                              const std::vector<MassIdSample>& samples,
                              SwlsPriorResidual* prior,
                              std::vector<SwlsDynamicResidual>* dynamics,
                              std::vector<SwlsMeasurementResidual>* measurements);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// @brief The "swls" MassEstimator.
std::unique_ptr<MassEstimator> make_swls_estimator(const ModelBasedTuning& tuning);

}  // namespace vid::massid
