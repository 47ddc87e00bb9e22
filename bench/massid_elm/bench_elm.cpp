/// @file bench_elm.cpp
/// @brief Training time of ELM / RELM (seed Algorithm 1, eq. 29; seed: ~3.4 s for 500 hidden
/// nodes on 5 datasets) against naive pseudo-inverse implementations, OSELM per-sample update
/// (Algorithm 2) and per-sample prediction.
///
/// Data: 5 synthetic runs with the study's size (25 s at 100 Hz = 2501 samples each, see
/// config/massid/study.yaml); solve cost depends only on the sizes, not on the content.
/// Arguments: {hidden nodes, train_stride}. stride 2 is the default model setting (2461 rows
/// per run -> 1231 used, 6155 in all), stride 1 uses every sample (12305 rows).
#include <benchmark/benchmark.h>

#include "massid/elm/mass_model.h"
#include "massid/elm/oselm.h"
#include "synthetic_run.h"

namespace vid::massid::elm {
namespace {

const std::vector<MassIdRun>& five_runs() {
  static const std::vector<MassIdRun> runs = [] {
    std::vector<MassIdRun> r;
    for (unsigned i = 0; i < 5; ++i) {
      testing::SyntheticSpec spec;
      spec.duration = 25.0;
      spec.sigma_v = 0.02;
      spec.seed = 100 + i;
      spec.omega = 0.6 + 0.1 * i;
      spec.mass = [i](double t) { return 1.0 + 0.1 * i - 0.01 * t; };
      r.push_back(testing::make_synthetic_run(spec));
    }
    return r;
  }();
  return runs;
}

std::vector<const MassIdRun*> pointers() {
  std::vector<const MassIdRun*> p;
  for (const auto& r : five_runs()) p.push_back(&r);
  return p;
}

/// Whole training: features, normalization, hidden layer, output weights.
void BM_Train(benchmark::State& state, Method method) {
  DataDrivenOptions options;
  options.hidden_nodes = static_cast<int>(state.range(0));
  options.lambda = 1e-5;
  options.oselm_chunk = 50;
  ModelConfig config;
  config.features.train_stride = static_cast<int>(state.range(1));
  const auto runs = pointers();
  TrainStats stats;
  for (auto _ : state) {
    auto model = MassModel::train(method, runs, options, config, &stats);
    benchmark::DoNotOptimize(model);
  }
  state.counters["rows"] = static_cast<double>(stats.rows);
}
BENCHMARK_CAPTURE(BM_Train, relm, Method::kRelm)
    ->Args({500, 2})->Args({500, 1})->Args({1000, 2})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Train, elm, Method::kElm)
    ->Args({500, 2})->Args({500, 1})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Train, oselm_chunk50, Method::kOselm)
    ->Args({500, 2})->Unit(benchmark::kMillisecond);

/// The same training with a naive solver: features, hidden layer, then beta = pinv(H) T
/// (CompleteOrthogonalDecomposition::pseudoInverse) or (H^T H + lambda I)^-1 H^T T with an
/// explicit inverse.
void BM_TrainNaive(benchmark::State& state, bool pinv) {
  const int L = static_cast<int>(state.range(0));
  FeatureConfig features;
  features.train_stride = static_cast<int>(state.range(1));
  const auto runs = pointers();
  for (auto _ : state) {
    const RunFeatures data = extract_training_set(runs, features);
    const Normalizer n = Normalizer::fit(data.X, data.y);
    const HiddenLayer layer(features.dimension(), L, 1, 2.0 / std::sqrt(features.dimension()));
    const Eigen::MatrixXd H = layer.activations(n.apply(data.X));
    const Eigen::VectorXd T = n.apply_target(data.y);
    Eigen::MatrixXd beta = pinv ? solve_elm_naive_pinv(H, T) : solve_relm_naive_inverse(H, T, 1e-5);
    benchmark::DoNotOptimize(beta);
  }
}
BENCHMARK_CAPTURE(BM_TrainNaive, pinv_cod, true)
    ->Args({500, 2})->Args({500, 1})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TrainNaive, explicit_inverse, false)
    ->Args({500, 2})->Args({500, 1})->Unit(benchmark::kMillisecond);

/// Hidden-layer outputs H and normalized targets T of the training set for L nodes, and an
/// OSELM initialized on its first 2 L samples (the sequential phase starts at row 2 L).
struct OselmSetup {
  Eigen::MatrixXd H;
  Eigen::VectorXd T;
  OnlineSequentialElm os;
};
OselmSetup make_oselm(int L) {
  FeatureConfig features;
  const RunFeatures data = extract_training_set(pointers(), features);
  const Normalizer n = Normalizer::fit(data.X, data.y);
  const HiddenLayer layer(features.dimension(), L, 1, 2.0 / std::sqrt(features.dimension()));
  OselmSetup s{layer.activations(n.apply(data.X)), n.apply_target(data.y),
               OnlineSequentialElm(L, 1, 1e-5)};
  s.os.initialize(s.H.topRows(2 * L), s.T.head(2 * L));
  return s;
}

/// OSELM sequential phase, one sample (rank-one Woodbury update of P and beta).
void BM_OselmUpdateOne(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  auto [H, T, os] = make_oselm(L);
  Eigen::Index r = 2 * L;
  for (auto _ : state) {
    os.update_one(H.row(r).transpose(), T.segment(r, 1));
    if (++r == H.rows()) r = 2 * L;
  }
}
BENCHMARK(BM_OselmUpdateOne)->Arg(100)->Arg(500)->Arg(1000)->Unit(benchmark::kMicrosecond);

/// OSELM chunk update cost per sample (chunk of state.range(1) samples).
void BM_OselmChunkPerSample(benchmark::State& state) {
  const int L = static_cast<int>(state.range(0));
  const int chunk = static_cast<int>(state.range(1));
  auto [H, T, os] = make_oselm(L);
  Eigen::Index r = 2 * L;
  for (auto _ : state) {
    os.update(H.middleRows(r, chunk), T.segment(r, chunk));
    r += chunk;
    if (r + chunk > H.rows()) r = 2 * L;
  }
  state.SetItemsProcessed(state.iterations() * chunk);
}
BENCHMARK(BM_OselmChunkPerSample)->Args({500, 10})->Args({500, 50})->Unit(benchmark::kMicrosecond);

/// Online prediction: one sample through the causal extractor and the 500-node network.
void BM_PredictPerSample(benchmark::State& state) {
  DataDrivenOptions options;
  options.hidden_nodes = static_cast<int>(state.range(0));
  ElmMassEstimator est(MassModel::train(Method::kRelm, pointers(), options));
  const MassIdRun& run = five_runs()[0];
  est.reset(run.info, run.samples[0]);
  size_t k = 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(est.update(run.samples[k]));
    if (++k == run.samples.size()) {
      est.reset(run.info, run.samples[0]);
      k = 1;
    }
  }
}
BENCHMARK(BM_PredictPerSample)->Arg(500)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace vid::massid::elm
