#pragma once
// Run the estimator system (vid_system) on a simulator folder (docs/formats.md §1, feature
// level) read with vid::io::DatasetReader, with parameters built in code (sim_params), and
// evaluate against the folder's ground truth (the library's ATE with position+yaw alignment,
// world force RMSE).
#include <filesystem>
#include <string>
#include <vector>

#include "io/dataset_reader.h"
#include "vid_system/config.h"
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

/// Generate (vid_sim --features-only) unless the folder was made by this vid_sim binary from this
/// scenario text, seed and duration (its made_by.txt; otherwise it is regenerated);
/// duration_s > 0 shortens the scenario.
/// noise_free: the preset with `noise: false` (exact sensors).
std::filesystem::path ensure_sim_dataset(const std::string& preset, int seed, double duration_s = 0.0,
                                         bool noise_free = false);

/// Filter noise for exact (noise: false) simulator data.
void set_noise_free_params(EstimatorParams& p);

/// The System's parameters on simulator folders: the folder's own cameras, IMU, rotor and
/// vehicle calibration, feat0 features, ground-truth initialization, the thrust noise from the
/// rotor-speed noise at hover, 0.5 px feature noise (the presets'), estimator defaults otherwise.
/// Change the returned parameters in code to diagnose (vio_core_diag_sim).
system::SystemParams sim_params(const io::DatasetCalibration& cal, PropagationMode mode);

/// Run one mode over the folder with sim_params; ground-truth initialization.
/// noise_free: filter noise of set_noise_free_params (for exact data).
SimMetrics run_on_dataset(const std::filesystem::path& folder, PropagationMode mode, bool noise_free = false);
/// Run the folder with the given parameters (sim_params, changed); ground truth is pushed.
SimMetrics run_on_dataset(const std::filesystem::path& folder, const system::SystemParams& params);

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
