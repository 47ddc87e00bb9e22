// Micro-benchmarks of the estimator core: accelerometer update, one propagation step and the
// EKF part of a visual update, on a full window (11 clones; dynamics mode with the default
// world-frame force and force-rate state: 21 + 66 states).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "geometry/so3.h"
#include "vio_core/accel_noise.h"
#include "vio_core/ekf_update.h"
#include "vio_core/force_jump.h"
#include "vio_core/initializer.h"
#include "vio_core/propagation.h"

namespace {
using namespace vid;

FilterState full_window(PropagationMode mode, int clones, ForceFrame frame = EstimatorParams{}.force_frame,
                        double force_rate_random_walk = EstimatorParams{}.force_rate_random_walk) {
  EstimatorParams p;
  p.mode = mode;
  p.force_frame = frame;
  p.force_rate_random_walk = force_rate_random_walk;
  FilterState s(mode == PropagationMode::kDynamics, frame, force_rate_random_walk > 0.0);
  ImuState x;
  x.T_WI.q = so3::quat_exp(Eigen::Vector3d(0.1, -0.2, 0.3));
  s.initialize(0, x, initial_covariance(p, x.T_WI.q));
  ImuInterval u;
  u.dt = 0.0025;
  u.gyro0 = u.gyro1 = Eigen::Vector3d(0.1, 0.2, -0.1);
  u.drive0 = u.drive1 = Eigen::Vector3d(0.0, 0.0, 9.81);
  for (int c = 0; c < clones; ++c) {
    for (int k = 0; k < 13; ++k) propagate(s, u, p);
    s.augment_clone();
  }
  return s;
}

// Arg 0: clones; arg 1: 1 = world-frame force with force rate (default), 0 = body-frame
// random walk (the seed's model).
void BM_AccelUpdate(benchmark::State& st) {
  const bool world = st.range(1) != 0;
  FilterState s = full_window(PropagationMode::kDynamics, static_cast<int>(st.range(0)),
                              world ? ForceFrame::kWorld : ForceFrame::kBody, world ? 0.5 : 0.0);
  const Eigen::Vector3d Tm(0, 0, 9.81);
  Eigen::Vector3d a = Tm;
  for (auto _ : st) {
    a.x() = -a.x() + 1e-3;  // alternate the reading so the state keeps moving
    const UpdateResult r = accel_update(s, a, Tm, 4.0, 0.0);
    benchmark::DoNotOptimize(r);
  }
  st.counters["dim"] = s.dim();
}
BENCHMARK(BM_AccelUpdate)->Args({11, 1})->Args({11, 0})->Args({0, 1});

// The force-jump detector's per-sample work as the estimator does it after every accelerometer
// update: push one innovation and test every window of a full 64-sample buffer (white
// innovations: no detection, the common case). Arg 1: with a vibration excess on every sample
// (the coloured sums of docs/model.md eq. (22)).
void BM_ForceJumpPushTest(benchmark::State& st) {
  const EstimatorParams p;
  ForceJumpDetector det(p);
  std::mt19937 rng(5);
  std::normal_distribution<double> nd(0.0, 2.0);
  std::vector<AccelInnovation> samples(1024);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    samples[k].t_ns = static_cast<TimeNs>(k) * 2'500'000;
    samples[k].w = Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    samples[k].S = 4.0 * Eigen::Matrix3d::Identity();
    if (st.range(0) == 1) samples[k].S_vib = 1.0 * Eigen::Matrix3d::Identity();
  }
  for (int k = 0; k < p.force_jump_window; ++k) det.push(samples[static_cast<std::size_t>(k)]);
  std::size_t k = 0;
  for (auto _ : st) {
    det.push(samples[k++ & 1023]);
    auto j = det.test();
    if (j) det.clear();
    benchmark::DoNotOptimize(j);
  }
}
BENCHMARK(BM_ForceJumpPushTest)->Arg(0)->Arg(1);

// The vibration-aware noise per accelerometer sample (accel_noise.h): the windowed high-pass
// power and the median of the window's squares (100 samples at 400 Hz) on each axis.
void BM_AccelNoiseAdd(benchmark::State& st) {
  AccelNoiseAdapter noise(0.25, 0.25, 400.0);
  std::mt19937 rng(3);
  std::normal_distribution<double> nd(0.0, 0.5);
  std::vector<Eigen::Vector3d> r(1024);
  for (Eigen::Vector3d& x : r) x = Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
  const Eigen::Vector3d S = Eigen::Vector3d::Constant(0.26);
  std::size_t k = 0;
  for (auto _ : st) {
    noise.add(r[k++ & 1023], S);
    benchmark::DoNotOptimize(noise.excess_var());
  }
}
BENCHMARK(BM_AccelNoiseAdd);

void BM_PropagationStep(benchmark::State& st) {
  const PropagationMode mode = st.range(0) ? PropagationMode::kDynamics : PropagationMode::kImu;
  EstimatorParams p;
  p.mode = mode;
  FilterState s = full_window(mode, 11);
  ImuInterval u;
  u.dt = 0.0025;
  u.gyro0 = Eigen::Vector3d(0.1, 0.2, -0.1);
  u.gyro1 = Eigen::Vector3d(0.12, 0.18, -0.1);
  u.drive0 = Eigen::Vector3d(0.1, 0.0, 9.81);
  u.drive1 = Eigen::Vector3d(0.1, 0.05, 9.8);
  for (auto _ : st) {
    propagate(s, u, p);
    benchmark::ClobberMemory();
  }
  st.counters["dim"] = s.dim();
}
BENCHMARK(BM_PropagationStep)->Arg(1)->Arg(0);

// EKF half of the MSCKF update: QR-compressed H with as many rows as touched clone columns
// (66) and 40 features x (2*11 - 3) = 760 rows before compression (compression is not here).
void BM_VisualEkfUpdate(benchmark::State& st) {
  FilterState s0 = full_window(PropagationMode::kDynamics, 11);
  const int m = 66;
  std::mt19937 rng(1);
  std::normal_distribution<double> nd(0, 1);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(m, s0.dim());
  for (int i = 0; i < m; ++i)
    for (int j = s0.imu_dim() + i; j < s0.dim(); ++j) H(i, j) = nd(rng);  // upper-triangular like R of QR
  Eigen::VectorXd r(m);
  for (int i = 0; i < m; ++i) r(i) = 1e-3 * nd(rng);
  const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(m, m) * 1e-5;
  for (auto _ : st) {
    st.PauseTiming();
    FilterState s = s0;
    st.ResumeTiming();
    const UpdateResult res = ekf_update(s, H, r, R);
    benchmark::DoNotOptimize(res);
  }
}
BENCHMARK(BM_VisualEkfUpdate)->Unit(benchmark::kMicrosecond);

void BM_CloneAugmentMarginalize(benchmark::State& st) {
  FilterState s = full_window(PropagationMode::kDynamics, 11);
  for (auto _ : st) {
    s.augment_clone();
    s.marginalize_oldest_clone();
  }
}
BENCHMARK(BM_CloneAugmentMarginalize);

}  // namespace
