// Diagnostic program (not a test): Monte-Carlo average NEES over seeds.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "run_helpers.h"

int main(int argc, char** argv) {
  using namespace vid;
  using namespace vid::test;
  const double dur = std::atof(argv[1]);
  const int runs = std::atoi(argv[2]);
  const bool imu = std::string(argv[3]) == "imu";
  const bool vis = std::atoi(argv[4]) != 0;
  const bool fej = argc > 5 ? std::atoi(argv[5]) != 0 : true;
  std::vector<double> nt, np, nf;
  std::vector<double> ts;
  for (int k = 0; k < runs; ++k) {
    SynthConfig c;
    c.duration = dur;
    c.noisy = true;
    c.seed = 100 + k;
    const SynthData d = generate(c);
    EstimatorConfig pc = matching_config(c, d, imu ? PropagationMode::kImu : PropagationMode::kDynamics);
    pc.params.visual_update = vis;
    pc.params.use_fej = fej;
    const RunResult r = run_estimator(c, d, pc, true, 1000 + k);
    if (nt.empty()) { nt.assign(r.errors.size(), 0); np = nt; nf = nt; for (auto& e : r.errors) ts.push_back(e.t); }
    for (std::size_t i = 0; i < r.errors.size() && i < nt.size(); ++i) {
      const RunError& e = r.errors[i];
      nt[i] += e.e_theta.dot(e.P_theta.ldlt().solve(e.e_theta)) / runs;
      np[i] += e.e_p.dot(e.P_p.ldlt().solve(e.e_p)) / runs;
      if (!imu) nf[i] += e.e_F_I.dot(e.P_F.ldlt().solve(e.e_F_I)) / runs;
    }
  }
  for (std::size_t i = 0; i < nt.size(); i += nt.size() / 20)
    std::printf("t %5.2f nees th %.2f p %.2f F %.2f\n", ts[i], nt[i], np[i], nf[i]);
}
