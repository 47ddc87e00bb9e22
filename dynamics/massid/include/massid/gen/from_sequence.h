#pragma once
/// @file from_sequence.h
/// @brief A study run made from a simulated VID sequence folder (ground truth, rotor speeds,
/// mass0), so the study's filters and the VIO can be scored on the same mass profile.

#include <cstdint>
#include <filesystem>

#include "massid/run_data.h"
#include "types/measurements.h"

namespace vid::massid::gen {

/// @brief How a sequence becomes a study run.
struct FromSequenceSettings {
  double rate_hz = 100.0;             ///< the study's sample rate
  double sigma_q = 0.005;             ///< attitude noise [rad] (the study's default)
  double sigma_p = 0.01;              ///< position noise [m]
  double sigma_v = 0.02;              ///< velocity noise [m/s]
  double initial_mass_factor = 1.0;   ///< initial guess = factor x vehicle.yaml mass (the VIO's m0)
  std::uint64_t seed = 1;             ///< measurement-noise seed
};

/// @brief The run plus where its t = 0 lies in the sequence's clock.
struct SequenceRun {
  MassIdRun run;
  TimeNs t0_ns = 0;
};

/// @brief Sample SEQ (or SEQ/mav0) on the study grid t_k = t0 + k / rate over the span that
/// ground truth, rotor0 and mass0 all cover:
/// q, p, v = ground truth interpolated at t_k (linear; q on the geodesic) plus the study's
/// measurement noise; w_I = Log(R_k^T R_k+1) / dt from the true attitudes (the body rate that,
/// held over the interval, gives the true rotation, as the study's commands are); thrust_cmd =
/// the mean collective thrust sum k_i n_i^2 of the rotor samples in [t_k, t_k+1) (the latest
/// one before when there is none); mass_true = mass0 interpolated at t_k.
/// RunInfo: trajectory = @p name, mass_profile "sequence", index 0, gravity and the initial
/// guess from vehicle.yaml.
/// @throws io::DatasetError naming the folder when a stream is missing or the span is empty
SequenceRun run_from_sequence(const std::filesystem::path& sequence, const std::string& name,
                              const FromSequenceSettings& settings);

}  // namespace vid::massid::gen
