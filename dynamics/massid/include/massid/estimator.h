#pragma once
/// @file estimator.h
/// @brief The one interface every mass-identification method implements (EKF, MSCKF, UKF,
/// SWLS, ELM, RELM, OSELM), so the study runner times and scores them the same way.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "massid/run_data.h"

namespace vid::massid {

/// @brief An online mass estimator fed one sample at a time.
class MassEstimator {
 public:
  virtual ~MassEstimator() = default;
  /// @brief Method name as used on the command line ("ekf", "ukf", "msckf", "swls", "vio", "elm", ...).
  virtual std::string name() const = 0;
  /// @brief Start a run: initial state from the first sample, mass from info.initial_mass_guess.
  virtual void reset(const RunInfo& info, const MassIdSample& first) = 0;
  /// @brief Process the next sample; return the current mass estimate [kg] at sample.t.
  virtual double update(const MassIdSample& sample) = 0;
};

/// @brief Options of the data-driven methods (ELM family).
struct DataDrivenOptions {
  int hidden_nodes = 500;
  double lambda = 1e-5;          ///< RELM / OSELM ridge weight (ignored by plain ELM)
  std::uint64_t seed = 1;        ///< input weights and biases
  int oselm_initial_samples = 0; ///< 0: the method's default
  int oselm_chunk = 1;           ///< samples per OSELM update
  double forgetting = 1.0;       ///< OSELM forgetting factor in (0, 1]; 1 = none
};

/// @brief Train a data-driven method ("elm", "relm", "oselm") on the given runs and return an
/// estimator that predicts the mass of unseen runs. Implemented in src/elm/.
/// @throws std::invalid_argument on an unknown method or empty training set
std::unique_ptr<MassEstimator> train_data_driven(const std::string& method,
                                                 const std::vector<const MassIdRun*>& training,
                                                 const DataDrivenOptions& options);

/// @brief Root-mean-square percentage error [%] (docs/model.md eq. (56)):
/// sqrt(mean(((m_hat - m) / m)^2)) * 100.
/// @throws std::invalid_argument on empty or unequal-length input
double rmspe(const std::vector<double>& m_hat, const std::vector<double>& m);

}  // namespace vid::massid
