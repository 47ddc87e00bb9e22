#pragma once
// Run the pipeline on a simulator folder (DESIGN §4, feature level) read with
// vid::io::DatasetReader; undistort features with vid::CameraModel; evaluate against the
// folder's ground truth (ATE with position+yaw alignment, world force RMSE).
#include <filesystem>
#include <string>

#include "vio_core/estimator_params.h"

namespace vid::test {

struct SimMetrics {
  double ate_posyaw_m = 0.0;
  double force_rmse_W = 0.0;   // m/s^2, against force0 / mass
  long estimates = 0;
  long visual_updates = 0;
  long features_used = 0;
  long features_rejected = 0;
  long frames = 0;
  long obs_without_norm = 0;
  long accel_rejected = 0;
  std::string status;
  double mean_frame_ms = 0.0;
};

/// Generate (vid_sim --features-only) unless the folder already has feat0/data.csv.
std::filesystem::path ensure_sim_dataset(const std::string& preset, int seed);

/// Run one mode over the folder; ground-truth initialization.
SimMetrics run_on_dataset(const std::filesystem::path& folder, PropagationMode mode);

}  // namespace vid::test
