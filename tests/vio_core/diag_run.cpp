// Diagnostic program (not a test): prints error/NEES statistics of one synthetic run.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "run_helpers.h"

int main(int argc, char** argv) {
  using namespace vid;
  using namespace vid::test;
  SynthConfig c;
  c.duration = argc > 1 ? std::atof(argv[1]) : 20.0;
  c.noisy = true;
  c.seed = argc > 2 ? std::atoi(argv[2]) : 3;
  const bool imu = argc > 3 && std::string(argv[3]) == "imu";
  if (argc > 4) c.pixel_sigma = std::atof(argv[4]);
  if (argc > 5) { c.gyro_density *= std::atof(argv[5]); c.accel_density *= std::atof(argv[5]); c.thrust_density *= std::atof(argv[5]); }
  const SynthData d = generate(c);
  EstimatorConfig pc = matching_config(c, d, imu ? PropagationMode::kImu : PropagationMode::kDynamics);
  if (argc > 6) pc.params.use_fej = std::atoi(argv[6]) != 0;
  if (argc > 7) pc.params.window_size = std::atoi(argv[7]);
  const RunResult r = run_estimator(c, d, pc);
  std::printf("status %s %s\n", to_string(r.status).c_str(), r.message.c_str());
  const auto& k = r.counters;
  std::printf("frames %ld vis upd %ld feat used %ld rej %ld accel %ld/%ld\n", k.frames, k.visual_updates,
              k.features_used, k.features_rejected, k.accel_updates, k.accel_rejected);
  for (std::size_t i = 0; i < r.errors.size(); i += 400) {
    const RunError& e = r.errors[i];
    const double nt = e.e_theta.dot(e.P_theta.ldlt().solve(e.e_theta));
    const double np = e.e_p.dot(e.P_p.ldlt().solve(e.e_p));
    const double nf = imu ? 0 : e.e_F_I.dot(e.P_F.ldlt().solve(e.e_F_I));
    std::printf("t %5.1f |dth| %.4f |dp| %.4f |dF| %.4f  sig_p %.4f sig_F %.4f  nees th %.2f p %.2f F %.2f\n", e.t,
                e.e_theta.norm(), e.e_p.norm(), e.e_F_I.norm(), std::sqrt(e.P_p.trace()),
                std::sqrt(e.P_F.trace()), nt, np, nf);
  }
}
