#pragma once
// Run the estimator over a synthetic sequence and collect errors against the analytic truth.
#include <map>
#include <vector>

#include "consistency.h"
#include "geometry/so3.h"
#include "synthetic.h"
#include "vio_core/estimator.h"
#include "vio_core/initializer.h"

namespace vid::test {

struct RunError {
  double t = 0;
  Eigen::Vector3d e_theta, e_p, e_F_I;  // estimate minus truth (theta: Log(R_true^T R_est))
  Eigen::Matrix3d P_theta, P_p, P_F;
  Eigen::Vector3d F_W_est, F_W_true;
};

struct RunResult {
  std::vector<RunError> errors;
  FilterStatus status = FilterStatus::kOk;
  std::string message;
  EstimatorCounters counters;
  std::vector<FrameTimings> frames;
};

/// init_seed != 0: the initial estimate is the truth (with the generator's true biases)
/// perturbed by one sample of the initial covariance (needed for an honest NEES).
inline RunResult run_estimator(const SynthConfig& c, const SynthData& d, const EstimatorConfig& pc,
                              bool init_from_truth = true, unsigned init_seed = 0) {
  Estimator estimator(pc);
  std::map<TimeNs, const TruthState*> truth;
  for (const TruthState& s : d.truth) truth[s.t_ns] = &s;
  RunResult out;
  estimator.set_estimate_callback([&](const EstimateOutput& e) {
    auto it = truth.find(e.t_ns);
    if (it == truth.end()) return;
    const TruthState& s = *it->second;
    RunError r;
    r.t = ns_to_s(e.t_ns);
    r.e_theta = so3::boxminus(e.x.T_WI.q, s.q);
    r.e_p = e.x.T_WI.p - s.p;
    r.e_F_I = e.F_ext_I - s.F_I;
    r.P_theta = e.cov_theta;
    r.P_p = e.cov_p;
    r.P_F = e.cov_F_I;
    r.F_W_est = e.F_ext_W;
    r.F_W_true = s.F_W;
    out.errors.push_back(r);
  });
  estimator.set_frame_callback([&](const FrameTimings& f) { out.frames.push_back(f); });
  if (init_from_truth) {
    ImuState x0 = initial_state(c);
    const Eigen::MatrixXd P0 = initial_covariance(pc.params, x0.T_WI.q);
    if (init_seed != 0) {
      x0.b_g = c.b_g;  // around the generator's true biases
      x0.b_a = c.b_a;
      perturb_by_covariance(x0, P0, init_seed);
    }
    estimator.initialize(0, x0, P0);
  }
  for (const Measurement& m : d.stream) estimator.push(m);
  estimator.finish();
  out.status = estimator.status();
  out.message = estimator.status_message();
  out.counters = estimator.counters();
  return out;
}

}  // namespace vid::test
