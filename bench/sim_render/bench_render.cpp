// Rendering speed: one 640x480 frame (VID calibration, radtan) of the default room scene,
// at 1x1 and 2x2 supersampling, with a camera moving around the room centre. Median of
// repetitions: run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>

#include "sim/render/renderer.h"
#include "sim/render/scene.h"

namespace {

const vid::sim::Scene& scene() {
  static const vid::sim::Scene s = [] {
    vid::sim::SceneConfig c;
    c.texture_seed = 5;
    c.checkerboard.enabled = true;
    return vid::sim::Scene(c);
  }();
  return s;
}

vid::CameraCalib vid_calib() {
  vid::CameraCalib c;
  c.intrinsics << 382.59014892578125, 382.59014892578125, 323.421142578125, 242.06617736816406;
  c.distortion_coeffs << -0.05, 0.01, 0.0005, -0.0003;
  return c;
}

Eigen::Isometry3d pose(int k) {
  const double yaw = 0.37 * k;
  const Eigen::Vector3d z = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), -0.2).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, z.cross(x), z;
  T.translation() = scene().config().room_center + Eigen::Vector3d(0.5 * std::sin(0.1 * k), 0.3, 0.0);
  return T;
}

void BM_RenderFrame(benchmark::State& state) {
  const int ss = static_cast<int>(state.range(0));
  vid::sim::Renderer renderer(scene(), vid_calib(), ss);
  cv::Mat img;
  vid::sim::FrameAppearance app;
  app.noise_sigma = 2.0;
  int k = 0;
  for (auto _ : state) {
    renderer.render(pose(k++ % 17), app, &img);
    benchmark::DoNotOptimize(img.data);
  }
}
BENCHMARK(BM_RenderFrame)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The vid17_hard image model at 2x2: 8 ms exposure while moving 1 m/s sideways and turning
// 0.6 rad/s (motion blur: a few sub-poses), vignetting, shot + read noise, flicker.
void BM_RenderExposure(benchmark::State& state) {
  vid::sim::Renderer renderer(scene(), vid_calib(), 2);
  cv::Mat img;
  vid::sim::FrameAppearance app;
  app.noise_sigma = 1.5;
  app.electrons_per_level = 40.0;
  app.vignetting = 0.25;
  app.flicker_amplitude = 0.1;
  app.exposure_s = 0.008;
  int k = 0;
  for (auto _ : state) {
    const Eigen::Isometry3d T0 = pose(k++ % 17);
    const vid::sim::PoseAtTime T_at = [&](double dt) {
      Eigen::Isometry3d T = T0;
      T.translation() += T0.linear().col(0) * dt;
      T.linear() = T0.linear() * Eigen::AngleAxisd(0.6 * dt, Eigen::Vector3d::UnitY()).toRotationMatrix();
      return T;
    };
    renderer.render(T_at, app, &img);
    benchmark::DoNotOptimize(img.data);
  }
}
BENCHMARK(BM_RenderExposure)->Unit(benchmark::kMillisecond);

}  // namespace
