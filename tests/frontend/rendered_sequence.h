#pragma once
// Rendered simulator sequences for the frontend scoring tests: vid_sim renders a preset once
// into the build tree and later runs reuse it while vid_sim and the preset are unchanged.
#include <Eigen/Core>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "sim/scenario.h"
#include "sim/simulator.h"

namespace vid::test {

namespace fs = std::filesystem;

inline const fs::path kSim = fs::path(VID_BINARY_DIR) / "bin" / "vid_sim";
inline const fs::path kPresets = fs::path(VID_SOURCE_DIR) / "config" / "sim";

struct Rendered {
  fs::path dir;
  std::string error;  ///< empty on success
};

/// Render `preset` for `duration` s unless a rendering newer than vid_sim and the preset exists.
inline Rendered render(const std::string& preset, int duration) {
  const fs::path scenario = kPresets / preset;
  Rendered r;
  r.dir = fs::path(VID_BINARY_DIR) / "tests" / "frontend" / "rendered" /
          (scenario.stem().string() + "_" + std::to_string(duration) + "s");
  if (!fs::exists(kSim)) return {r.dir, "build vid_sim first: " + kSim.string()};
  if (!fs::exists(scenario)) return {r.dir, "missing preset " + scenario.string()};
  const fs::path marker = r.dir / "rendered.ok";
  const bool fresh = fs::exists(marker) &&
                     fs::last_write_time(marker) > fs::last_write_time(kSim) &&
                     fs::last_write_time(marker) > fs::last_write_time(scenario);
  if (fresh) return r;
  fs::remove_all(r.dir);
  fs::create_directories(r.dir.parent_path());
  const std::string log = r.dir.string() + ".log";
  const std::string cmd = kSim.string() + " --scenario " + scenario.string() + " --out " +
                          r.dir.string() + " --duration " + std::to_string(duration) + " > " +
                          log + " 2>&1";
  if (std::system(cmd.c_str()) != 0) return {r.dir, "vid_sim failed (see " + log + "): " + cmd};
  std::ofstream(marker) << "ok\n";
  return r;
}

/// The simulator's rotation from the scene world to the ground-truth world of a rendering of
/// `preset` for `duration` s with the preset's seed (score_sequence's R_GS).
inline Eigen::Matrix3d scene_to_groundtruth(const std::string& preset, int duration) {
  sim::Scenario sc = sim::load_scenario(kPresets / preset);
  sim::apply_run_options(sc, std::nullopt, static_cast<double>(duration), "");
  return sim::Simulator(sc).R_GS();
}

}  // namespace vid::test
