// Cost of the in-flight initializer (vio_core/dynamic_initializer.h): one alignment of a full
// 1 s window (16 of the 20 or 40 Hz stereo frames, up to 120 landmarks, 400 Hz IMU) on an analytic flight
// through a room, as tests/vio_core/test_dynamic_init.cpp flies it. The estimator tries one per
// camera frame until one succeeds.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "geometry/so3.h"
#include "vio_core/dynamic_initializer.h"

namespace {
using namespace vid;
using Eigen::Matrix3d;
using Eigen::Vector3d;

Matrix3d rot(double u) {
  return so3::exp(Vector3d(0.0, 0.0, 0.7 * u)) * so3::exp(Vector3d(0.15 * std::sin(1.1 * u), 0.1 * std::cos(0.9 * u), 0));
}

// Initializer fed with everything up to (not including) the frame at t_end; that frame in *last.
DynamicInitializer primed(int window_frames_hz, FeatureFrame* last) {
  std::vector<CameraCalib> cams(2);
  for (int c = 0; c < 2; ++c) {
    cams[c].cam_id = c;
    cams[c].intrinsics = Eigen::Vector4d(400, 400, 320, 240);
    Matrix3d R_IC;
    R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    cams[c].T_IC.linear() = R_IC;
    cams[c].T_IC.translation() = Vector3d(0.1, c == 0 ? 0.05 : -0.05, 0.0);
  }
  EstimatorParams p;
  p.mode = PropagationMode::kImu;
  p.pixel_noise_px = 0.5;
  DynamicInitializer init(p, cams);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> n01;
  std::vector<Vector3d> lm;
  for (int i = 0; i < 3000; ++i) {
    const double az = M_PI * u(rng), z = 2.0 * u(rng);
    lm.emplace_back(6.0 * std::cos(az), 6.0 * std::sin(az), z);
  }
  const int per_frame = 400 / window_frames_hz;
  for (int i = 0; i <= 400; ++i) {
    const double t = 1.0 + i / 400.0;
    const Vector3d p_W(1.5 * std::sin(0.8 * t), std::cos(0.6 * t), 0.3 * std::sin(1.3 * t));
    const Vector3d acc(-0.96 * std::sin(0.8 * t), -0.36 * std::cos(0.6 * t), -0.507 * std::sin(1.3 * t));
    const Matrix3d R = rot(t);
    const Vector3d w = so3::log(rot(t - 1e-5).transpose() * rot(t + 1e-5)) / 2e-5;
    const TimeNs tn = static_cast<TimeNs>(std::llround(t * 1e9));
    init.add_imu(tn, w, R.transpose() * (acc + Vector3d(0, 0, 9.81)) + 2.0 * Vector3d(n01(rng), n01(rng), n01(rng)),
                 Vector3d(0, 0, 9.81));
    if (i % per_frame != 0) continue;
    FeatureFrame f;
    f.t_ns = tn;
    for (std::size_t j = 0; j < lm.size(); ++j)
      for (const CameraCalib& c : cams) {
        const Vector3d X_C = c.T_IC.inverse() * (R.transpose() * (lm[j] - p_W));
        const Eigen::Vector2d xy = X_C.head<2>() / X_C.z();
        if (X_C.z() < 0.5 || std::abs(xy.x()) > 0.8 || std::abs(xy.y()) > 0.6) continue;
        FeatureObservation o;
        o.cam_id = c.cam_id;
        o.feature_id = j;
        o.uv_norm = xy + 0.5 / 400.0 * Eigen::Vector2d(n01(rng), n01(rng));
        o.has_norm = true;
        f.observations.push_back(o);
      }
    if (i == 400) {
      *last = f;
    } else {
      init.add_frame(f);
    }
  }
  return init;
}

void BM_InFlightInitWindow(benchmark::State& state) {
  FeatureFrame last;
  const DynamicInitializer base = primed(static_cast<int>(state.range(0)), &last);
  bool ok = true;
  for (auto _ : state) {
    state.PauseTiming();
    DynamicInitializer init = base;
    state.ResumeTiming();
    const auto r = init.add_frame(last);
    ok = ok && r.has_value();
    benchmark::DoNotOptimize(r);
  }
  if (!ok) state.SkipWithError("the window did not align");
}
BENCHMARK(BM_InFlightInitWindow)->Arg(20)->Arg(40)->Unit(benchmark::kMillisecond);

}  // namespace
