// Diagnostic program (not a test): run the pipeline on one simulator folder and print metrics.
// Usage: vio_core_diag_sim FOLDER [imu|dynamics]; env overrides as in sim_runner.cpp.
#include <cstdio>
#include <string>

#include "sim_runner.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: vio_core_diag_sim FOLDER [imu|dynamics]\n");
    return 2;
  }
  const vid::PropagationMode mode = argc > 2 && std::string(argv[2]) == "imu"
                                        ? vid::PropagationMode::kImu
                                        : vid::PropagationMode::kDynamics;
  const vid::test::SimMetrics m = vid::test::run_on_dataset(argv[1], mode);
  std::printf("status %s force_rmse_W %.4f ate %.4f vis_upd %ld used %ld rej %ld frames %ld accel_rej %ld frame_ms %.3f\n",
              m.status.c_str(), m.force_rmse_W, m.ate_posyaw_m, m.visual_updates, m.features_used,
              m.features_rejected, m.frames, m.accel_rejected, m.mean_frame_ms);
  return 0;
}
