/// @file bench_massid.cpp
/// @brief Mean update time of the model-based mass estimators (issue #10 targets: EKF <= 5 us,
/// UKF <= 7.5 us, MSCKF <= 20 us, SWLS <= 0.6 ms) on a generated loop run (constant mass),
/// and the SWLS with each Ceres linear solver.
#include <benchmark/benchmark.h>

#include "massid/filters/estimators.h"
#include "massid/gen/run_simulator.h"

namespace {

using namespace vid::massid;

const MassIdRun& loop_run() {
  static const MassIdRun run = [] {
    gen::GeneratorSettings s;
    s.duration_s = 10.0;
    return gen::simulate_run(s, "loop", "constant", 0, gen::run_seed(s.seed, "loop", "constant", 0)).run;
  }();
  return run;
}

void run_updates(benchmark::State& state, MassEstimator& est) {
  const MassIdRun& run = loop_run();
  est.reset(run.info, run.samples.front());
  std::size_t k = 1;
  double m = 0.0;
  for (auto _ : state) {
    m += est.update(run.samples[k]);
    if (++k == run.samples.size()) {
      state.PauseTiming();
      est.reset(run.info, run.samples.front());
      k = 1;
      state.ResumeTiming();
    }
  }
  benchmark::DoNotOptimize(m);
}

void BM_Update(benchmark::State& state, const std::string& method) {
  auto est = make_model_based_estimator(method);
  run_updates(state, *est);
}

void BM_SwlsSolver(benchmark::State& state, const std::string& solver) {
  ModelBasedTuning t;
  t.swls_linear_solver = solver;
  auto est = make_model_based_estimator("swls", t);
  run_updates(state, *est);
}

BENCHMARK_CAPTURE(BM_Update, ekf, std::string("ekf"));
BENCHMARK_CAPTURE(BM_Update, ukf, std::string("ukf"));
BENCHMARK_CAPTURE(BM_Update, msckf, std::string("msckf"));
BENCHMARK_CAPTURE(BM_Update, swls, std::string("swls"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SwlsSolver, dense_normal_cholesky, std::string("dense_normal_cholesky"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SwlsSolver, dense_qr, std::string("dense_qr"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SwlsSolver, sparse_normal_cholesky, std::string("sparse_normal_cholesky"))->Unit(benchmark::kMillisecond);

}  // namespace
