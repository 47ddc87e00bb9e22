/// @file massid_diag.cpp
/// @brief Diagnostic (not a test): simulate runs with the study generator and print RMSPE and
/// mean update time per model-based method.
/// Usage: massid_diag [trajectory] [profile] [runs] [key=value ...] (ModelBasedTuning fields;
/// vio_* keys: the "vio" method's EstimatorParams, e.g. vio_force_rw=0.02)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "massid/filters/estimators.h"
#include "massid/filters/study_runner.h"
#include "massid/filters/vio_filter.h"
#include "massid/gen/run_simulator.h"

int main(int argc, char** argv) {
  using namespace vid::massid;
  const std::string traj = argc > 1 ? argv[1] : "loop";
  const std::string prof = argc > 2 ? argv[2] : "constant";
  const int runs = argc > 3 ? std::stoi(argv[3]) : 3;
  gen::GeneratorSettings s;
  ModelBasedTuning tune;
  vid::EstimatorParams vio = vio_params_for_study();
  for (int a = 4; a < argc; ++a) {
    const std::string kv = argv[a];
    const auto eq = kv.find('=');
    const std::string k = kv.substr(0, eq);
    const double v = std::stod(kv.substr(eq + 1));
    if (k == "theta") tune.sigma_theta_rw = v;
    else if (k == "p") tune.sigma_p_rw = v;
    else if (k == "v") tune.sigma_v_rw = v;
    else if (k == "m") tune.sigma_m_rw_rel = v;
    else if (k == "m0") tune.sigma_m0_rel = v;
    else if (k == "thr") tune.change_threshold = v;
    else if (k == "tau") tune.change_tau_s = v;
    else if (k == "cs") tune.change_sigma_rel = v;
    else if (k == "hold") tune.change_holdoff_s = v;
    else if (k == "mtau") tune.msckf_change_tau_s = v;
    else if (k == "rewind") tune.change_rewind_samples = static_cast<int>(v);
    else if (k == "mthr") tune.msckf_change_threshold = v;
    else if (k == "msckf_window") tune.msckf_window = static_cast<int>(v);
    else if (k == "swls_window") tune.swls_window = static_cast<int>(v);
    else if (k == "swls_iter") tune.swls_max_iterations = static_cast<int>(v);
    else if (k == "vio_force_rw") vio.force_random_walk = v;
    else if (k == "vio_scale_rw") vio.thrust_scale_random_walk = v;
    else if (k == "vio_world_force") vio.force_frame = v > 0 ? vid::ForceFrame::kWorld : vid::ForceFrame::kBody;
    else if (k == "vio_thrust_noise") vio.thrust_noise_density = v;
    else { std::fprintf(stderr, "unknown key %s\n", k.c_str()); return 1; }
  }
  const std::vector<std::string> methods = model_based_methods();
  std::vector<double> sum(methods.size(), 0.0), sum_ms(methods.size(), 0.0);
  for (int i = 0; i < runs; ++i) {
    const MassIdRun run = gen::simulate_run(s, traj, prof, i, gen::run_seed(s.seed, traj, prof, i)).run;
    std::vector<std::unique_ptr<MassEstimator>> est;
    std::vector<MassEstimator*> raw;
    for (const std::string& m : methods) {
      est.push_back(m == "vio" ? make_vio_estimator(vio, tune) : make_model_based_estimator(m, tune));
      raw.push_back(est.back().get());
    }
    const RunResult r = evaluate_run(run, raw);
    std::printf("%s/%s run %d (m0 %.3f kg):", traj.c_str(), prof.c_str(), i, run.samples.front().mass_true);
    for (std::size_t j = 0; j < r.methods.size(); ++j) {
      const auto& m = r.methods[j];
      double worst = 0.0;  // worst relative error after 8 s (meaningful for "constant")
      for (std::size_t k = 0; k < run.samples.size(); ++k) {
        if (run.samples[k].t >= 8.0) worst = std::max(worst, std::abs(m.mass_hat[k] / run.samples[k].mass_true - 1.0));
      }
      std::printf("  %s %.2f%% (max %.1f%%) %.4fms", m.method.c_str(), m.rmspe_pct, 100 * worst, m.mean_update_cpu_ms);
      sum[j] += m.rmspe_pct;
      sum_ms[j] += m.mean_update_cpu_ms;
    }
    std::printf("\n");
  }
  std::printf("MEAN %s/%s:", traj.c_str(), prof.c_str());
  for (std::size_t j = 0; j < methods.size(); ++j) std::printf("  %s %.2f%% %.4fms", methods[j].c_str(), sum[j] / runs, sum_ms[j] / runs);
  std::printf("\n");
  return 0;
}
