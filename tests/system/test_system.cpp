// The System built from typed parameters and fed feature frames: it adds nothing to the
// estimator's own output (same estimates as the Estimator fed directly), reports status changes
// and frame timings to its observers, writes the docs/formats.md §2 files, and scores itself
// against pushed ground truth.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../vio_core/synthetic.h"
#include "vid_system/system.h"
#include "vio_core/initializer.h"

namespace vid::system {
namespace {

using test::SynthConfig;
using test::SynthData;

SystemParams params_for(const EstimatorConfig& pc) {
  SystemParams p;
  p.config.estimator = pc.params;
  p.config.cameras = pc.cameras;
  p.config.vehicle = pc.vehicle;
  p.features = FeatureSource::kFeat0;
  p.truth_vehicle = pc.vehicle;
  return p;
}

struct Fixture {
  SynthConfig c;
  SynthData d;
  EstimatorConfig pc;
  Fixture() {
    c.duration = 3.0;
    d = test::generate(c);
    pc = test::matching_config(c, d, PropagationMode::kDynamics);
  }
};

TEST(System, FeatureInputGivesTheEstimatorsEstimatesAndObserversSeeEveryStep) {
  Fixture f;
  const ImuState x0 = test::initial_state(f.c);
  const Eigen::MatrixXd P0 = initial_covariance(f.pc.params, x0.T_WI.q);

  Estimator estimator(f.pc);
  std::vector<EstimateOutput> want;
  estimator.set_estimate_callback([&](const EstimateOutput& e) { want.push_back(e); });
  estimator.initialize(0, x0, P0);
  for (const Measurement& m : f.d.stream) estimator.push(m);
  estimator.finish();

  System sys(params_for(f.pc));
  std::vector<EstimateOutput> got;
  std::vector<FilterStatus> statuses;
  long frames = 0;
  sys.on_estimate([&](const EstimateOutput& e) { got.push_back(e); });
  sys.on_frame([&](const FrameTimings&) { ++frames; });
  sys.on_status([&](FilterStatus s, const std::string&) { statuses.push_back(s); });
  sys.initialize(0, x0, P0);
  for (const Measurement& m : f.d.stream) sys.push(m);
  sys.finish();

  ASSERT_GT(want.size(), 1000u);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    ASSERT_EQ(got[i].t_ns, want[i].t_ns);
    ASSERT_EQ(got[i].x.T_WI.p, want[i].x.T_WI.p);
    ASSERT_EQ(got[i].F_ext_W, want[i].F_ext_W);
  }
  EXPECT_EQ(statuses, std::vector<FilterStatus>{FilterStatus::kOk});
  EXPECT_EQ(frames, estimator.counters().frames);
  EXPECT_EQ(sys.counters().visual_updates, estimator.counters().visual_updates);
  EXPECT_EQ(sys.estimates(), static_cast<long>(got.size()));
  EXPECT_EQ(sys.tracked_cameras(), 0);  // feat0: no frontend
  EXPECT_EQ(sys.summary()["mode"], "dynamics");
}

TEST(System, ScoresItselfAgainstPushedGroundTruthAndWritesTheOutputs) {
  Fixture f;
  const std::filesystem::path out = std::filesystem::path(VID_BINARY_DIR) / "test_system_out";
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  SystemParams p = params_for(f.pc);
  p.out_dir = out;
  System sys(p);
  const ImuState x0 = test::initial_state(f.c);
  sys.initialize(0, x0, initial_covariance(f.pc.params, x0.T_WI.q));
  std::vector<EstimateOutput> est;
  sys.on_estimate([&](const EstimateOutput& e) { est.push_back(e); });
  // The truth as a dataset gives it, in time order with the sensors: poses and the force in
  // newtons (the mass comes from truth_vehicle).
  std::size_t k = 0;
  for (const Measurement& m : f.d.stream) {
    for (; k < f.d.truth.size() && f.d.truth[k].t_ns <= stamp_of(m); ++k) {
      const test::TruthState& s = f.d.truth[k];
      GroundTruthSample g;
      g.t_ns = s.t_ns;
      g.T_WI = {s.q, s.p};
      sys.push(g);
      sys.push(ForceSample{s.t_ns, s.F_W * f.pc.vehicle.mass_kg});
    }
    sys.push(m);
  }
  sys.finish();
  sys.close_outputs();

  // The library's ATE over the same series.
  Vec3Series e, g;
  for (const EstimateOutput& x : est) {
    e.t_ns.push_back(x.t_ns);
    e.v.push_back(x.x.T_WI.p);
  }
  for (const test::TruthState& s : f.d.truth) {
    g.t_ns.push_back(s.t_ns);
    g.v.push_back(s.p);
  }
  const auto ate = ate_posyaw(e, g);
  ASSERT_TRUE(ate);
  const nlohmann::json s = sys.summary();
  EXPECT_EQ(s["ate_posyaw_m"].get<double>(), ate->rmse_m);
  EXPECT_LT(ate->rmse_m, 0.05);
  EXPECT_TRUE(s.contains("force_rmse_world_mps2"));
  EXPECT_TRUE(s.contains("force_rmse_body_mps2"));

  std::ifstream state(out / "state.csv");
  std::string line;
  long rows = -1;  // header
  while (std::getline(state, line)) ++rows;
  EXPECT_EQ(rows, static_cast<long>(est.size()));
}

}  // namespace
}  // namespace vid::system
