/// @file study_runner.cpp
/// @brief Study runner: run selection, per-update timing, RMSPE, worker threads.
#include "massid/filters/study_runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <numeric>
#include <random>
#include <stdexcept>
#include <thread>

#include <time.h>

#include "massid/filters/estimators.h"

namespace vid::massid {
namespace {

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

bool is_data_driven(const std::string& m) { return m == "elm" || m == "relm" || m == "oselm"; }

/// @brief Estimators of one worker thread (the ELM family is trained per worker: the trained
/// estimators keep per-run state and cannot be shared between threads).
std::vector<std::unique_ptr<MassEstimator>> make_estimators(
    const StudyRunOptions& o, const std::vector<const MassIdRun*>& training) {
  std::vector<std::unique_ptr<MassEstimator>> out;
  for (const std::string& m : o.methods) {
    if (is_data_driven(m)) {
      out.push_back(train_data_driven(m, training, o.data_driven));
    } else {
      out.push_back(make_model_based_estimator(m, o.tuning));
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> available_methods() {
  std::vector<std::string> m = model_based_methods();
  m.insert(m.end(), {"elm", "relm", "oselm"});
  return m;
}

std::vector<RunInfo> select_runs(const DatasetIndex& index, int runs_per_case, std::uint64_t seed) {
  std::map<std::pair<std::string, std::string>, std::vector<int>> cases;
  for (int i = 0; i < static_cast<int>(index.runs.size()); ++i) {
    cases[{index.runs[i].trajectory, index.runs[i].mass_profile}].push_back(i);
  }
  std::vector<int> chosen;
  std::mt19937_64 rng(seed);
  for (auto& [key, ids] : cases) {
    std::shuffle(ids.begin(), ids.end(), rng);
    const int n = std::min<int>(runs_per_case, static_cast<int>(ids.size()));
    chosen.insert(chosen.end(), ids.begin(), ids.begin() + n);
  }
  std::sort(chosen.begin(), chosen.end());
  std::vector<RunInfo> out;
  for (int i : chosen) out.push_back(index.runs[i]);
  return out;
}

RunResult evaluate_run(const MassIdRun& run, const std::vector<MassEstimator*>& estimators) {
  if (run.samples.empty()) throw std::invalid_argument("run " + std::to_string(run.info.index) + " has no samples");
  RunResult res;
  res.info = run.info;
  res.samples = run.samples;
  std::vector<double> m_true;
  for (const MassIdSample& s : run.samples) m_true.push_back(s.mass_true);
  for (MassEstimator* est : estimators) {
    MethodRunResult r;
    r.method = est->name();
    est->reset(run.info, run.samples.front());
    r.mass_hat.reserve(run.samples.size());
    r.mass_hat.push_back(run.info.initial_mass_guess);
    // Whole-loop totals: clock reads per call would cost as much as an EKF update.
    const double cpu0 = thread_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t k = 1; k < run.samples.size(); ++k) r.mass_hat.push_back(est->update(run.samples[k]));
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_s = thread_cpu_seconds() - cpu0;
    const double n = std::max<double>(1.0, static_cast<double>(run.samples.size() - 1));
    r.mean_update_ms = 1e3 * wall_s / n;
    r.mean_update_cpu_ms = 1e3 * cpu_s / n;
    r.rmspe_pct = rmspe(r.mass_hat, m_true);
    res.methods.push_back(std::move(r));
  }
  return res;
}

void run_study(const DatasetIndex& index, const StudyRunOptions& o,
               const std::function<void(const RunResult&, int, int)>& on_result) {
  const std::vector<std::string> known = available_methods();
  for (const std::string& m : o.methods) {
    if (std::find(known.begin(), known.end(), m) == known.end()) {
      throw std::invalid_argument("unknown or unavailable method '" + m + "'");
    }
  }
  const std::vector<RunInfo> runs = select_runs(index, o.runs_per_case, o.selection_seed);
  // Training runs of the ELM family: runs not evaluated, a few per case.
  std::vector<MassIdRun> training_runs;
  if (std::any_of(o.methods.begin(), o.methods.end(), is_data_driven)) {
    std::map<std::pair<std::string, std::string>, int> taken;
    for (const RunInfo& info : index.runs) {
      const bool evaluated = std::any_of(runs.begin(), runs.end(), [&](const RunInfo& r) {
        return r.trajectory == info.trajectory && r.mass_profile == info.mass_profile && r.index == info.index;
      });
      int& n = taken[{info.trajectory, info.mass_profile}];
      if (evaluated || n >= o.train_runs_per_case) continue;
      training_runs.push_back(load_run(index, info));
      ++n;
    }
    if (training_runs.empty()) throw std::invalid_argument("no runs left to train the ELM family on");
  }
  std::vector<const MassIdRun*> training;
  for (const MassIdRun& r : training_runs) training.push_back(&r);

  std::atomic<int> next{0};
  std::mutex mu;
  int done = 0;
  std::exception_ptr error;
  auto worker = [&]() {
    try {
      auto estimators = make_estimators(o, training);
      std::vector<MassEstimator*> raw;
      for (auto& e : estimators) raw.push_back(e.get());
      for (int i = next++; i < static_cast<int>(runs.size()); i = next++) {
        const RunResult res = evaluate_run(load_run(index, runs[i]), raw);
        std::lock_guard<std::mutex> lock(mu);
        on_result(res, ++done, static_cast<int>(runs.size()));
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mu);
      if (!error) error = std::current_exception();
      next = static_cast<int>(runs.size());
    }
  };
  const int n_threads = std::max(1, std::min<int>(o.threads, static_cast<int>(runs.size())));
  std::vector<std::thread> pool;
  for (int t = 0; t < n_threads; ++t) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace vid::massid
