#pragma once
/// @file study.h
/// @brief The data-driven study of seed section 6.3 (tables 1-3, figures 13-17): split a
/// generated dataset by run, train ELM / RELM / OSELM, score held-out runs.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "massid/elm/mass_model.h"
#include "massid/run_data.h"

namespace vid::massid::elm {

/// @brief Train/test split of one trajectory, by whole runs (no test run is seen in training).
struct RunSplit {
  std::vector<RunInfo> train;
  std::vector<RunInfo> test;
};

/// @brief Split of `trajectory`: training dataset k (k = 0..n_train-1) is the run with
/// index k / P of profile k % P (P = number of profiles in the index, in manifest order), so
/// n_train = 5 takes one run of each profile; the test set is runs test_first ..
/// test_first + test_per_profile - 1 of every profile.
/// @throws std::invalid_argument when a needed run is missing or train and test overlap
RunSplit split_by_run(const DatasetIndex& index, const std::string& trajectory, int n_train,
                      int test_per_profile, int test_first);

/// @brief Loads runs once and keeps them (the study reuses them across configurations).
class RunCache {
 public:
  explicit RunCache(const DatasetIndex& index) : index_(index) {}
  const MassIdRun& get(const RunInfo& info);
  std::vector<const MassIdRun*> get_all(const std::vector<RunInfo>& infos);

 private:
  const DatasetIndex& index_;
  std::map<std::string, std::unique_ptr<MassIdRun>> runs_;
};

/// @brief Score of a model on held-out runs.
struct HeldOutScore {
  double rmse_percent = 0.0;       ///< RMSPE (docs/model.md eq. (56)) pooled over test samples that have
                                   ///< features (after the first longest-window seconds)
  double rmse_full_percent = 0.0;  ///< same over every sample, the warm-up at the initial guess
  long samples = 0;
};

/// @brief Per-sample predictions of every test run and the pooled scores.
HeldOutScore score_held_out(const MassModel& model, const std::vector<const MassIdRun*>& test,
                            std::vector<std::vector<double>>* predictions = nullptr);

/// @brief One row of tables 1-3.
struct StudyRow {
  std::string trajectory;
  std::string method;
  int hidden = 0;
  double lambda = 0.0;
  int n_train = 0;
  long rows = 0;             ///< training samples
  double train_seconds = 0;  ///< features + hidden layer + output weights (wall clock)
  double weight_norm = 0.0;  ///< |beta|_F
  double train_rmse_percent = 0.0;
  HeldOutScore test;
};

/// @brief Train `method` on `train` and score on `test`; the training time is the minimum
/// over `repeats` trainings (the machine is shared).
StudyRow run_configuration(Method method, const std::vector<const MassIdRun*>& train,
                           const std::vector<const MassIdRun*>& test,
                           const DataDrivenOptions& options, const ModelConfig& config,
                           int repeats, std::shared_ptr<const MassModel>* model_out = nullptr);

}  // namespace vid::massid::elm
