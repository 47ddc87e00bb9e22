/// @file study.cpp
/// @brief Split by run, held-out scoring and one table row of the data-driven study (seed
/// section 6.3, tables 1-3).
#include "massid/elm/study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>

namespace vid::massid::elm {
namespace {

std::string key_of(const RunInfo& r) {
  return r.trajectory + "/" + r.mass_profile + "/" + std::to_string(r.index);
}

}  // namespace

RunSplit split_by_run(const DatasetIndex& index, const std::string& trajectory, int n_train,
                      int test_per_profile, int test_first) {
  std::vector<std::string> profiles;
  std::map<std::string, const RunInfo*> by_key;
  for (const RunInfo& r : index.runs) {
    if (r.trajectory != trajectory) continue;
    if (std::find(profiles.begin(), profiles.end(), r.mass_profile) == profiles.end()) {
      profiles.push_back(r.mass_profile);
    }
    by_key[key_of(r)] = &r;
  }
  if (profiles.empty()) {
    throw std::invalid_argument(index.root.string() + "/manifest.yaml: no runs of trajectory '" +
                                trajectory + "'");
  }
  auto find = [&](const std::string& profile, int i) -> const RunInfo& {
    RunInfo probe;
    probe.trajectory = trajectory;
    probe.mass_profile = profile;
    probe.index = i;
    auto it = by_key.find(key_of(probe));
    if (it == by_key.end()) {
      throw std::invalid_argument(index.root.string() + "/manifest.yaml: no run " +
                                  key_of(probe) + " (generate more runs)");
    }
    return *it->second;
  };
  RunSplit split;
  const int P = static_cast<int>(profiles.size());
  std::set<std::string> train_keys;
  for (int k = 0; k < n_train; ++k) {
    split.train.push_back(find(profiles[static_cast<size_t>(k % P)], k / P));
    train_keys.insert(key_of(split.train.back()));
  }
  for (const std::string& p : profiles) {
    for (int i = test_first; i < test_first + test_per_profile; ++i) {
      split.test.push_back(find(p, i));
      if (train_keys.count(key_of(split.test.back()))) {
        throw std::invalid_argument("split_by_run: test run " + key_of(split.test.back()) +
                                    " is also a training run (raise test_first)");
      }
    }
  }
  return split;
}

const MassIdRun& RunCache::get(const RunInfo& info) {
  const std::string key = key_of(info);
  auto it = runs_.find(key);
  if (it == runs_.end()) {
    it = runs_.emplace(key, std::make_unique<MassIdRun>(load_run(index_, info))).first;
  }
  return *it->second;
}

std::vector<const MassIdRun*> RunCache::get_all(const std::vector<RunInfo>& infos) {
  std::vector<const MassIdRun*> out;
  for (const RunInfo& r : infos) out.push_back(&get(r));
  return out;
}

HeldOutScore score_held_out(const MassModel& model, const std::vector<const MassIdRun*>& test,
                            std::vector<std::vector<double>>* predictions) {
  std::vector<double> est, truth, est_all, truth_all;
  if (predictions) predictions->clear();
  const double warmup = model.config().features.windows.back();
  for (const MassIdRun* run : test) {
    const std::vector<double> m_hat = model.predict_run(*run);
    for (size_t k = 0; k < m_hat.size(); ++k) {
      const MassIdSample& s = run->samples[k];
      est_all.push_back(m_hat[k]);
      truth_all.push_back(s.mass_true);
      if (s.t - run->samples.front().t >= warmup) {
        est.push_back(m_hat[k]);
        truth.push_back(s.mass_true);
      }
    }
    if (predictions) predictions->push_back(m_hat);
  }
  HeldOutScore score;
  if (est.empty()) throw std::invalid_argument("score_held_out: no test samples");
  score.rmse_percent = rmspe(est, truth);
  score.rmse_full_percent = rmspe(est_all, truth_all);
  score.samples = static_cast<long>(est.size());
  return score;
}

StudyRow run_configuration(Method method, const std::vector<const MassIdRun*>& train,
                           const std::vector<const MassIdRun*>& test,
                           const DataDrivenOptions& options, const ModelConfig& config,
                           int repeats, std::shared_ptr<const MassModel>* model_out) {
  StudyRow row;
  row.method = method_name(method);
  row.hidden = options.hidden_nodes;
  row.lambda = method == Method::kElm ? 0.0 : options.lambda;
  row.n_train = static_cast<int>(train.size());
  row.train_seconds = INFINITY;
  std::shared_ptr<const MassModel> model;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    TrainStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    model = MassModel::train(method, train, options, config, &stats);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row.train_seconds = std::min(row.train_seconds, s);
    row.rows = stats.rows;
    row.weight_norm = stats.weight_norm;
    row.train_rmse_percent = stats.train_rmse_percent;
  }
  if (!train.empty()) row.trajectory = train.front()->info.trajectory;
  row.test = score_held_out(*model, test);
  if (model_out) *model_out = model;
  return row;
}

}  // namespace vid::massid::elm
