// One camera and a vehicle that stands still before it flies (euroc_like: hovers 3.5 s at
// 1.4 m, then a random flight; static initialization as vid_run does it). A parallax-free
// window carries no information on translation for an MSCKF, so without the zero-velocity
// update (vio_core/zero_velocity.h) the IMU alone integrates the initial tilt / accelerometer
// bias error into velocity and the mono filter never recovers; stereo does not need it.
#include <gtest/gtest.h>

#include <cstdio>

#include "ratchet.h"
#include "sim_system.h"

namespace {
using namespace vid;
using namespace vid::test;

constexpr double kMonoAte = 0.021;  // m, measured (see the test)

SimMetrics run_mono(const std::filesystem::path& folder, double max_parallax_px) {
  io::ReaderOptions opt;
  opt.read_images = false;
  system::SystemParams params = sim_params(io::DatasetReader(folder, opt).calibration(), PropagationMode::kImu);
  EstimatorParams& p = params.config.estimator;
  p.init_mode = InitMode::kStatic;
  p.use_stereo = false;
  p.zero_velocity_max_parallax_px = max_parallax_px;
  const SimMetrics m = run_on_dataset(folder, params);
  std::printf("euroc_like_short mono, zero_velocity_max_parallax_px %.1f: ATE %.4f m, %ld visual updates (%s)\n",
              max_parallax_px, m.ate_posyaw_m, m.visual_updates, m.status.c_str());
  return m;
}

TEST(MonoStill, HoverBeforeFlightDoesNotDrift) {
  const auto folder = ensure_sim_dataset("euroc_like_short", 1);
  const SimMetrics with = run_mono(folder, EstimatorParams{}.zero_velocity_max_parallax_px);
  EXPECT_EQ(with.status, "ok");
  // Measured 0.0209 m (182d56e, seed 1; other seeds not measured, so 1.2 x the test's own value);
  // the earlier 0.15 let a 7x regression pass.
  expect_ratchet("euroc_like_short mono ATE [m]", with.ate_posyaw_m, 1.2 * kMonoAte, kMonoAte);
  // The scenario is the hard case: without the update the same run is lost.
  const SimMetrics without = run_mono(folder, 0.0);
  EXPECT_GT(without.ate_posyaw_m, 10.0 * with.ate_posyaw_m);
}

}  // namespace
