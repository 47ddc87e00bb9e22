/// Timing of the MSCKF visual update on the synthetic scene of the tests: BM_MsckfUpdate is the
/// whole update as the estimator applies it (target <= 1 ms for 40 features x 11 clones,
/// stereo), BM_BuildVisualUpdate and the others its parts.
/// Run: bench_vio_msckf --benchmark_repetitions=10 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <random>

#include "synthetic_scene.h"
#include "vio_core/msckf/clone_poses.h"
#include "vio_core/msckf/linear_algebra.h"
#include "vio_core/msckf/triangulation.h"
#include "vio_core/ekf_update.h"
#include "vio_core/estimator_params.h"
#include "vio_core/msckf/visual_update.h"
#include "vio_core/state.h"

namespace {

using namespace vid::msckf;
using vid::msckf::testing::make_scene;
using vid::msckf::testing::Scene;
using vid::msckf::testing::SceneOptions;

struct Setup {
  Scene scene;
  std::vector<ClonePose> clones;
  Eigen::MatrixXd P;
  VisualUpdateParams params;
};

/// 1 px noise, clone estimates 0.1 deg / 1 cm off the truth, dense prior covariance.
Setup make_setup(int features, int clones, bool stereo, bool estimate_extrinsics) {
  SceneOptions opt;
  opt.num_features = features;
  opt.num_clones = clones;
  opt.stereo = stereo;
  opt.pixel_sigma_norm = 1.0 / opt.focal;
  Setup s{make_scene(opt), {}, {}, {}};
  int n = s.scene.state_dim;
  if (estimate_extrinsics) {
    for (CameraExtrinsic& e : s.scene.extrinsics) {
      e.cov_index = n;
      n += 6;
    }
  }
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = 1e-3 * g(rng);
  s.P = A * A.transpose() + 1e-4 * Eigen::MatrixXd::Identity(n, n);
  s.clones = s.scene.clones_true;
  for (ClonePose& c : s.clones) {
    c.R_WI = c.R_WI * vid::so3::exp(Eigen::Vector3d(g(rng), g(rng), g(rng)) * 0.002);
    c.p_WI += Eigen::Vector3d(g(rng), g(rng), g(rng)) * 0.01;
    c.R_WI_fej = c.R_WI;
    c.p_WI_fej = c.p_WI;
  }
  s.params.sigma_norm = 1.0 / opt.focal;
  s.params.chi2_multiplier = 1e3;  // time the full path for every feature
  return s;
}

void BM_BuildVisualUpdate(benchmark::State& state) {
  Setup s = make_setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                       state.range(2) != 0, state.range(3) != 0);
  s.params.compression =
      state.range(4) != 0 ? Compression::kNormalEquations : Compression::kQr;
  int used = 0;
  Eigen::Index rows = 0;
  for (auto _ : state) {
    const VisualLinearSystem sys =
        build_visual_update(s.scene.tracks, s.clones, s.scene.extrinsics, s.P, s.params);
    used = sys.features_used;
    rows = sys.H.rows();
    benchmark::DoNotOptimize(sys.H.data());
  }
  state.counters["features_used"] = used;
  state.counters["rows_out"] = static_cast<double>(rows);
}
BENCHMARK(BM_BuildVisualUpdate)
    ->ArgNames({"features", "clones", "stereo", "extrinsics", "normal_eq"})
    ->Args({40, 11, 1, 0, 0})
    ->Args({40, 11, 1, 0, 1})
    ->Args({40, 11, 1, 1, 0})
    ->Args({40, 11, 1, 1, 1})
    ->Args({40, 11, 0, 0, 0})
    ->Args({40, 11, 0, 0, 1})
    ->Args({100, 11, 1, 0, 1})
    ->Unit(benchmark::kMicrosecond);

/// Filter state of the estimator (dynamics mode, default force model) whose clones are the
/// setup's clones, with a dense random covariance over all of it.
vid::FilterState make_state(const Setup& s) {
  vid::FilterState st{vid::EstimatorParams{}};
  st.initialize(0, vid::ImuState{}, Eigen::MatrixXd::Identity(st.imu_dim(), st.imu_dim()));
  for (const ClonePose& c : s.clones) {
    st.set_time(c.t_ns);
    st.imu().T_WI = {Eigen::Quaterniond(c.R_WI), c.p_WI};
    st.reset_imu_fej();
    st.augment_clone();
  }
  const int n = st.dim();
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = 1e-3 * g(rng);
  st.P() = A * A.transpose() + 1e-4 * Eigen::MatrixXd::Identity(n, n);
  return st;
}

/// The whole MSCKF update as vid::Estimator does it: clone poses from the state,
/// build_visual_update with normal-equation compression (the estimator default), then
/// ekf_update with R = noise_var * I. The state copy per iteration is not timed.
void BM_MsckfUpdate(benchmark::State& state) {
  Setup s = make_setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                       state.range(2) != 0, false);
  s.params.compression = Compression::kNormalEquations;
  const vid::FilterState st0 = make_state(s);
  int used = 0;
  Eigen::Index rows = 0;
  int applied = 0;
  for (auto _ : state) {
    state.PauseTiming();
    vid::FilterState st = st0;
    state.ResumeTiming();
    const std::vector<ClonePose> clones = clone_poses(st);
    const VisualLinearSystem sys =
        build_visual_update(s.scene.tracks, clones, s.scene.extrinsics, st.P(), s.params);
    if (sys.H.rows() > 0) {
      const Eigen::MatrixXd R =
          Eigen::MatrixXd::Identity(sys.H.rows(), sys.H.rows()) * sys.noise_var;
      applied += vid::ekf_update(st, sys.H, sys.r, R).applied ? 1 : 0;
    }
    used = sys.features_used;
    rows = sys.H.rows();
    benchmark::DoNotOptimize(st.P().data());
  }
  state.counters["features_used"] = used;
  state.counters["rows_out"] = static_cast<double>(rows);
  state.counters["applied"] =
      static_cast<double>(applied) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_MsckfUpdate)
    ->ArgNames({"features", "clones", "stereo"})
    ->Args({40, 11, 1})
    ->Unit(benchmark::kMicrosecond);

void BM_Triangulate22Rays(benchmark::State& state) {
  const Setup s = make_setup(1, 11, true, false);
  std::vector<CameraRay> rays;
  for (const TrackObservation& o : s.scene.tracks[0].obs) {
    for (const ClonePose& c : s.scene.clones_true) {
      if (c.t_ns != o.t_ns) continue;
      const Eigen::Isometry3d& T = s.scene.extrinsics[o.cam_id].T_IC;
      rays.push_back({c.R_WI * T.linear(), c.p_WI + c.R_WI * T.translation(), o.uv_norm});
    }
  }
  for (auto _ : state) {
    const TriangulationResult r = triangulate(rays, TriangulationParams{});
    benchmark::DoNotOptimize(r.p_W.data());
  }
}
BENCHMARK(BM_Triangulate22Rays)->Unit(benchmark::kMicrosecond);

void BM_CompressQr1640x66(benchmark::State& state) {
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd H0(1640, 66);
  Eigen::VectorXd r0(1640);
  for (int i = 0; i < 1640; ++i) {
    r0(i) = g(rng);
    for (int j = 0; j < 66; ++j) H0(i, j) = g(rng);
  }
  for (auto _ : state) {
    Eigen::MatrixXd H = H0;
    Eigen::VectorXd r = r0;
    compress_qr(&H, &r);
    benchmark::DoNotOptimize(H.data());
  }
}
BENCHMARK(BM_CompressQr1640x66)->Unit(benchmark::kMicrosecond);

}  // namespace
