/// @file bench_sim.cpp
/// @brief Simulator micro-benchmarks: RK4 step, controller update, one simulated second of
/// the vid17_like flight without cameras (physics + controller + sensors).

#include <benchmark/benchmark.h>

#include "sim/controller.h"
#include "sim/scenario.h"
#include "sim/simulator.h"

namespace {

vid::sim::Scenario vid17() {
  return vid::sim::load_scenario(std::string(VID_SOURCE_DIR) + "/config/sim/vid17_like.yaml");
}

void BM_Rk4Step(benchmark::State& state) {
  const vid::sim::Scenario sc = vid17();
  vid::sim::Simulator sim(sc);
  vid::dynamics::QuadrotorState x = sim.initial_state();
  const Eigen::VectorXd cmd = x.rotor_speeds;
  double t = 0.0;
  for (auto _ : state) {
    x = sim.model().rk4_step(t, 1e-3, x, cmd, sim.environment());
    t += 1e-3;
    benchmark::DoNotOptimize(x.p_WI);
  }
}
BENCHMARK(BM_Rk4Step);

void BM_ControllerUpdate(benchmark::State& state) {
  const vid::sim::Scenario sc = vid17();
  vid::sim::Simulator sim(sc);
  vid::sim::GeometricController ctrl(sim.model(), sc.gains);
  vid::sim::ControllerInput in{5.0, sim.initial_state(), Eigen::Vector3d::Zero()};
  for (auto _ : state) benchmark::DoNotOptimize(ctrl.update(in, sim.trajectory(), 0.002));
}
BENCHMARK(BM_ControllerUpdate);

void BM_SimulatedSecond(benchmark::State& state) {
  vid::sim::Scenario sc = vid17();
  sc.duration_s = 1.0;
  sc.cameras.cameras.clear();
  vid::sim::SimSink sink;
  for (auto _ : state) {
    vid::sim::Simulator sim(sc);
    sim.run(sink);
  }
}
BENCHMARK(BM_SimulatedSecond)->Unit(benchmark::kMillisecond);

}  // namespace
