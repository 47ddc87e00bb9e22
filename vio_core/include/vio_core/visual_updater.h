#pragma once
/// @file visual_updater.h
/// @brief The MSCKF visual update as the estimator runs it (docs/model.md §7): its options
/// (pixel noise in normalized units, chi2 multiplier, minimum track length, compression,
/// triangulation) and the camera extrinsics built once from the configuration, then per frame
/// the stacked system of msckf/visual_update.h applied in one EKF correction. In the spirit of
/// OpenVINS's UpdaterMSCKF owning its options.

#include <vector>

#include "types/calibration.h"
#include "vio_core/estimator_params.h"
#include "vio_core/msckf/visual_update.h"
#include "vio_core/state.h"

namespace vid {

/// @brief Builds and applies the visual update of one frame.
class VisualUpdater {
 public:
  /// @param cameras by cam_id; the first one's focal lengths convert pixel_noise_px.
  VisualUpdater(const EstimatorParams& params, const std::vector<CameraCalib>& cameras);
  /// @brief The update from @p tracks over @p clones, applied to @p state when it has rows;
  /// the returned system's counts say what was used and rejected (its H, r are emptied).
  msckf::VisualLinearSystem update(FilterState& state, const std::vector<msckf::FeatureTrack>& tracks,
                                   const std::vector<msckf::ClonePose>& clones, bool* applied) const;
  const msckf::VisualUpdateParams& options() const { return options_; }

 private:
  msckf::VisualUpdateParams options_;
  std::vector<msckf::CameraExtrinsic> extrinsics_;
};

}  // namespace vid
