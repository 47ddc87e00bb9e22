#include "sim_test_util.h"

#include <cmath>

namespace vid::sim::test {

std::string preset_path(const std::string& name) { return std::string(VID_SOURCE_DIR) + "/config/sim/" + name + ".yaml"; }

Recording record(Scenario sc) {
  sc.cameras.cameras.clear();
  Simulator sim(sc);
  Recording rec;
  sim.run(rec);
  return rec;
}

double tracking_rmse(const Simulator& sim, const Recording& rec, double t_from_s) {
  double sum = 0.0;
  int n = 0;
  for (const GroundTruthSample& g : rec.gt) {
    const double t = static_cast<double>(g.t_ns - sim.scenario().start_time_ns) * 1e-9;
    if (t < t_from_s) continue;
    sum += (g.T_WI.p - sim.trajectory().eval(t).p).squaredNorm();
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : INFINITY;
}

}  // namespace vid::sim::test
