/// Whole-estimator cost per camera frame in dynamics mode, with and without fixed-lag smoothing
/// (docs/notes/smoothing.md; issue #22 asks that smoothing add <= 30 %). The
/// sequence is the tests' analytic synthetic one (tests/vio_core/synthetic.h: stereo 20 Hz,
/// IMU 400 Hz, rotor 100 Hz, a smooth external force, feature tracks without a frontend), so
/// the time is propagation + accelerometer updates + MSCKF + marginalization, no KLT.
/// Args: {lag [ms], clone period [ms]}; lag 0 = smoothing off.
/// Run: bench_vio_estimator --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <variant>

#include "synthetic.h"
#include "vio_core/estimator.h"
#include "vio_core/initializer.h"

namespace {

using namespace vid;
using namespace vid::test;

const SynthConfig& config() {
  static const SynthConfig c = [] {
    SynthConfig s;
    s.duration = 20.0;
    s.noisy = true;
    s.seed = 3;
    s.force_amplitude = 1.5;
    return s;
  }();
  return c;
}

const SynthData& data() {
  static const SynthData d = generate(config());
  return d;
}

void BM_EstimatorDynamics(benchmark::State& state) {
  const SynthConfig& c = config();
  const SynthData& d = data();
  EstimatorConfig pc = matching_config(c, d, PropagationMode::kDynamics);
  pc.params.smoother_lag_s = static_cast<double>(state.range(0)) * 1e-3;
  pc.params.smoother_clone_period_s = static_cast<double>(state.range(1)) * 1e-3;
  std::int64_t frames = 0, smoothed = 0;
  for (auto _ : state) {
    Estimator estimator(pc);
    estimator.set_frame_callback([&](const FrameTimings&) { ++frames; });
    estimator.set_smoothed_callback([&](const EstimateOutput&) { ++smoothed; });
    const ImuState x0 = initial_state(c);
    estimator.initialize(0, x0, initial_covariance(pc.params, x0.T_WI.q));
    for (const Measurement& m : d.stream) estimator.push(m);
    estimator.finish();
    if (estimator.status() != FilterStatus::kOk) state.SkipWithError("estimator did not finish ok");
  }
  // Seconds per camera frame (kIsRate | kInvert turns frames per second into seconds per frame).
  state.counters["s_per_frame"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["smoothed_per_run"] = static_cast<double>(smoothed) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_EstimatorDynamics)
    ->Args({0, 100})
    ->Args({300, 100})
    ->Args({300, 50})
    ->Args({1000, 100})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace
