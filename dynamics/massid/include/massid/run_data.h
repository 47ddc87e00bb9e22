#pragma once
/// @file run_data.h
/// @brief One simulated run of the mass-identification study (seed section 5.3) and its CSV
/// file. Shared contract of the data generator (src/gen/), the model-based methods
/// (src/filters/) and the data-driven methods (src/elm/).
///
/// CSV (one file per run, header line first, seconds and SI units):
/// `t,qw,qx,qy,qz,px,py,pz,vx,vy,vz,thrust_cmd,wx,wy,wz,mass_true`
/// q, p, v are the *measured* (noisy) attitude q_WI, position p_WI and velocity v_WI;
/// thrust_cmd is the commanded collective thrust [N] along z_I; w is the commanded body rate
/// in I [rad/s]; mass_true is the true mass [kg].

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "types/calibration.h"

namespace vid::massid {

/// @brief One sample of a run (a row of the CSV).
struct MassIdSample {
  double t = 0.0;                                          ///< [s] from the run start
  Eigen::Quaterniond q_WI = Eigen::Quaterniond::Identity();  ///< measured attitude
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();          ///< measured position [m]
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();          ///< measured velocity [m/s]
  double thrust_cmd = 0.0;                                 ///< commanded thrust [N]
  Eigen::Vector3d w_I = Eigen::Vector3d::Zero();           ///< commanded body rate [rad/s]
  double mass_true = 0.0;                                  ///< [kg]
};

/// @brief What a method needs to know about the run besides the samples (from the dataset's
/// manifest, not from the CSV).
struct RunInfo {
  std::string trajectory;     ///< random | loop | lemniscate | zigzag | square
  std::string mass_profile;   ///< constant | linear_decrease | step_drop | step_pickup | up_down
  int index = 0;              ///< run number within trajectory x profile
  std::uint64_t seed = 0;
  double gravity = kDefaultGravity;  ///< magnitude [m/s^2], g_W = [0, 0, -gravity]
  double initial_mass_guess = 0.0;  ///< the wrong nominal mass the controller and methods start from [kg]
  double sigma_q = 0.0;       ///< measurement noise of q (rad, per axis, local perturbation)
  double sigma_p = 0.0;       ///< measurement noise of p [m]
  double sigma_v = 0.0;       ///< measurement noise of v [m/s]
};

/// @brief A whole run.
struct MassIdRun {
  RunInfo info;
  std::vector<MassIdSample> samples;
};

/// @brief A generated study dataset on disk:
/// `DIR/manifest.yaml` (every run's RunInfo and the generator settings) and
/// `DIR/<trajectory>/<mass_profile>/run_<NNN>.csv` (NNN = index, 3 digits).
struct DatasetIndex {
  std::filesystem::path root;
  std::vector<RunInfo> runs;
};

/// @brief Read DIR/manifest.yaml. @throws std::runtime_error "FILE: key 'k': message"
DatasetIndex read_dataset_index(const std::filesystem::path& dir);
/// @brief DIR/<trajectory>/<mass_profile>/run_<NNN>.csv of a run.
std::filesystem::path run_csv_path(const std::filesystem::path& root, const RunInfo& info);
/// @brief Info plus samples of one run of an index.
MassIdRun load_run(const DatasetIndex& index, const RunInfo& info);

/// @brief Write a run's samples as the CSV above (17 significant digits, round-trips exactly).
/// @throws std::runtime_error naming the file when it cannot be written
void write_run_csv(const std::filesystem::path& file, const std::vector<MassIdSample>& samples);

/// @brief Read a run CSV.
/// @throws io-style std::runtime_error "FILE:LINE: message" naming the field at fault
std::vector<MassIdSample> read_run_csv(const std::filesystem::path& file);

}  // namespace vid::massid
