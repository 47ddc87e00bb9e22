/// @file dataset_generator.cpp
/// @brief Parallel generation of the study's runs; a shared job counter, one result slot per job.
#include "massid/gen/dataset_generator.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

#include "massid/gen/manifest.h"
#include "massid/run_data.h"

namespace vid::massid::gen {

GenerationResult generate_dataset(const GeneratorSettings& settings,
                                  const std::filesystem::path& out_dir, int threads,
                                  const std::function<void(int, int)>& progress,
                                  bool write_truth) {
  validate(settings);
  struct Job {
    std::string trajectory, profile;
    int index;
  };
  std::vector<Job> jobs;
  for (const auto& traj : settings.trajectories) {
    for (const auto& prof : settings.profiles) {
      std::filesystem::create_directories(out_dir / traj / prof);
      for (int i = 0; i < settings.runs; ++i) jobs.push_back({traj, prof, i});
    }
  }
  const int total = static_cast<int>(jobs.size());
  GenerationResult result;
  result.runs.resize(jobs.size());
  result.stats.resize(jobs.size());

  std::atomic<int> next{0}, done{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&]() {
    while (true) {
      const int j = next.fetch_add(1);
      if (j >= total) return;
      try {
        const Job& job = jobs[j];
        const std::uint64_t seed = run_seed(settings.seed, job.trajectory, job.profile, job.index);
        SimulatedRun sim = simulate_run(settings, job.trajectory, job.profile, job.index, seed);
        const std::filesystem::path csv = run_csv_path(out_dir, sim.run.info);
        write_run_csv(csv, sim.run.samples);
        if (write_truth) {
          std::filesystem::path truth = csv;
          truth.replace_filename(csv.stem().string() + "_truth.csv");
          write_truth_csv(truth, sim);
        }
        result.runs[j] = sim.run.info;
        result.stats[j] = sim.stats;
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(total);  // stop handing out work
      }
      done.fetch_add(1);
    }
  };
  int n_threads = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  n_threads = std::clamp(n_threads, 1, std::max(1, total));
  std::vector<std::thread> pool;
  for (int i = 0; i < n_threads; ++i) pool.emplace_back(worker);
  if (progress) {
    while (done.load() < total && !error) {
      progress(done.load(), total);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      std::lock_guard<std::mutex> lock(error_mutex);
      if (error) break;
    }
  }
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  if (progress) progress(total, total);

  write_manifest(out_dir, generator_settings_yaml(settings), result.runs);

  for (size_t j = 0; j < jobs.size();) {
    GroupSummary g;
    g.trajectory = jobs[j].trajectory;
    g.profile = jobs[j].profile;
    for (; j < jobs.size() && jobs[j].trajectory == g.trajectory && jobs[j].profile == g.profile; ++j) {
      const RunStats& st = result.stats[j];
      ++g.runs;
      g.position_rmse_mean_m += st.position_rmse_m;
      g.position_rmse_max_m = std::max(g.position_rmse_max_m, st.position_rmse_m);
      g.saturated_fraction_mean += st.saturated_fraction;
    }
    g.position_rmse_mean_m /= g.runs;
    g.saturated_fraction_mean /= g.runs;
    result.groups.push_back(g);
  }
  return result;
}

}  // namespace vid::massid::gen
