/// @file visual_updater.cpp
/// @brief VisualUpdater (visual_updater.h).
#include "vio_core/visual_updater.h"

#include "vio_core/ekf_update.h"

namespace vid {

VisualUpdater::VisualUpdater(const EstimatorParams& p, const std::vector<CameraCalib>& cameras) {
  for (const CameraCalib& c : cameras) {
    msckf::CameraExtrinsic e;
    e.T_IC = c.T_IC;
    extrinsics_.push_back(e);
  }
  if (!cameras.empty()) {
    const CameraCalib& c0 = cameras.front();
    options_.sigma_norm = p.pixel_noise_px / (0.5 * (c0.intrinsics[0] + c0.intrinsics[1]));
  }
  options_.chi2_multiplier = p.chi2_multiplier;
  options_.min_observations = p.min_track_length;
  options_.compression = p.msckf_normal_equations ? msckf::Compression::kNormalEquations : msckf::Compression::kQr;
  options_.triangulation.max_condition = p.triangulation_max_condition;
}

msckf::VisualLinearSystem VisualUpdater::update(FilterState& state, const std::vector<msckf::FeatureTrack>& tracks,
                                                const std::vector<msckf::ClonePose>& clones, bool* applied) const {
  msckf::VisualLinearSystem sys = msckf::build_visual_update(tracks, clones, extrinsics_, state.P(), options_);
  *applied = false;
  if (sys.H.rows() > 0) {
    const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(sys.H.rows(), sys.H.rows()) * sys.noise_var;
    *applied = ekf_update(state, sys.H, sys.r, R).applied;
  }
  sys.H.resize(0, 0);
  sys.r.resize(0);
  return sys;
}

}  // namespace vid
