#pragma once
// Run the pipeline on a simulator folder (docs/formats.md §1, feature level) read with
// vid::io::DatasetReader; undistort features with vid::CameraModel; evaluate against the
// folder's ground truth (ATE with position+yaw alignment, world force RMSE).
#include <filesystem>
#include <string>
#include <vector>

#include "vio_core/estimator_params.h"

namespace vid::test {

struct SimMetrics {
  double ate_posyaw_m = 0.0;
  double force_rmse_W = 0.0;   // m/s^2, against force0 / mass
  double force_err_max_after5_W = 0.0;  // largest |F_W error| 5 s after the start
  double pos_err_max_m = 0.0;           // largest |p error| (no alignment)
  double theta_err_max_rad = 0.0;       // largest orientation error
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

/// Generate (vid_sim --features-only) unless the folder already has feat0/data.csv;
/// duration_s > 0 shortens the scenario.
/// noise_free: the preset with `noise: false` (exact sensors).
std::filesystem::path ensure_sim_dataset(const std::string& preset, int seed, double duration_s = 0.0,
                                         bool noise_free = false);

/// Filter noise for exact (noise: false) simulator data.
void set_noise_free_params(EstimatorParams& p);

/// Run one mode over the folder; ground-truth initialization.
/// noise_free: filter noise of set_noise_free_params (for exact data).
SimMetrics run_on_dataset(const std::filesystem::path& folder, PropagationMode mode, bool noise_free = false);

/// @brief NEES (3 dof each) of orientation, position and body-frame F_ext at 10 Hz ground-truth
/// times; F is 0 in imu mode.
struct NeesSeries {
  std::vector<double> t, theta, p, F;
  std::string status;
};

/// Run one mode over the folder with the initial estimate drawn from the initial covariance
/// around the truth (seeded) and return the NEES series.
NeesSeries nees_on_dataset(const std::filesystem::path& folder, PropagationMode mode, unsigned init_seed);

}  // namespace vid::test
