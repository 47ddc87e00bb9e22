// Diagnostic program (not a test): run the estimator system on one simulator folder with the
// test parameters (sim_system.h: sim_params) and print metrics. To try other parameters,
// change them here in code, e.g. `params.config.estimator.force_random_walk = ...;`.
// Usage: vio_core_diag_sim FOLDER [imu|dynamics]
#include <cstdio>
#include <string>

#include "sim_system.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: vio_core_diag_sim FOLDER [imu|dynamics]\n");
    return 2;
  }
  const vid::PropagationMode mode = argc > 2 && std::string(argv[2]) == "imu"
                                        ? vid::PropagationMode::kImu
                                        : vid::PropagationMode::kDynamics;
  vid::io::ReaderOptions features_only;
  features_only.read_images = false;
  const vid::system::SystemParams params =
      vid::test::sim_params(vid::io::DatasetReader(argv[1], features_only).calibration(), mode);
  const vid::test::SimMetrics m = vid::test::run_on_dataset(argv[1], params);
  std::printf("status %s force_rmse_W %.4f ate %.4f vis_upd %ld used %ld rej %ld frames %ld accel_rej %ld frame_ms %.3f\n",
              m.status.c_str(), m.force_rmse_W, m.ate_posyaw_m, m.visual_updates, m.features_used,
              m.features_rejected, m.frames, m.accel_rejected, m.mean_frame_ms);
  return 0;
}
