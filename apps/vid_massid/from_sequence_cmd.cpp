/// @file from_sequence_cmd.cpp
/// @brief `vid_massid from-sequence`: simulated VID sequence folders -> a study dataset, so the
/// study's methods run on the same mass profiles as the VIO (dynamics/massid/README.md,
/// "Study filters and the VIO on the same flights").
#include <spdlog/spdlog.h>

#include <filesystem>
#include <memory>
#include <sstream>

#include "commands.h"
#include "massid/gen/from_sequence.h"
#include "massid/gen/manifest.h"

namespace vid::massid_app {
namespace {

struct FromSequenceOptions {
  std::vector<std::string> sequences;
  std::vector<std::string> names;
  std::string out;
  massid::gen::FromSequenceSettings settings;
};

int run_from_sequence(const FromSequenceOptions& o) {
  if (!o.names.empty() && o.names.size() != o.sequences.size()) {
    throw CLI::ValidationError("--name", "give one name per --sequence (or none)");
  }
  std::vector<massid::RunInfo> runs;
  std::ostringstream generator;  // where each run came from, and its t = 0 in the sequence clock
  generator << "source: from-sequence\nrate_hz: " << o.settings.rate_hz
            << "\ninitial_mass_factor: " << o.settings.initial_mass_factor << "\nsequences:\n";
  for (std::size_t i = 0; i < o.sequences.size(); ++i) {
    const std::filesystem::path seq = o.sequences[i];
    const std::string name = o.names.empty() ? std::filesystem::absolute(seq).lexically_normal().filename().string()
                                             : o.names[i];
    auto s = o.settings;
    s.seed = o.settings.seed + i;
    const massid::gen::SequenceRun r = massid::gen::run_from_sequence(seq, name, s);
    const auto csv = massid::run_csv_path(o.out, r.run.info);
    std::filesystem::create_directories(csv.parent_path());
    massid::write_run_csv(csv, r.run.samples);
    runs.push_back(r.run.info);
    generator << "  - {name: \"" << name << "\", path: \"" << std::filesystem::absolute(seq).string()
              << "\", t0_ns: " << r.t0_ns << "}\n";
    spdlog::info("{}: {} samples ({:.1f} s) from {}", name, r.run.samples.size(),
                 r.run.samples.size() / o.settings.rate_hz, seq.string());
  }
  massid::gen::write_manifest(o.out, generator.str(), runs);
  spdlog::info("wrote {}/manifest.yaml ({} runs)", o.out, runs.size());
  return 0;
}

}  // namespace

void add_from_sequence_command(CLI::App& cli, int* exit_code) {
  auto o = std::make_shared<FromSequenceOptions>();
  CLI::App* cmd = cli.add_subcommand(
      "from-sequence",
      "Turn simulated sequence folders (ground truth, rotor0, mass0) into a study dataset: "
      "noisy pose/velocity at the study's rate, thrust from the rotor speeds, true body rates");
  cmd->add_option("--sequence", o->sequences, "sequence folder (repeatable)")
      ->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--name", o->names, "run name per sequence, comma-separated (default: the folder's name)")->delimiter(',');
  cmd->add_option("--out", o->out, "output folder (manifest.yaml + <name>/sequence/run_000.csv)")
      ->required();
  cmd->add_option("--rate", o->settings.rate_hz, "sample rate [Hz]")
      ->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  cmd->add_option("--seed", o->settings.seed, "noise seed (sequence i uses seed + i)")
      ->capture_default_str();
  cmd->add_option("--initial-mass-factor", o->settings.initial_mass_factor,
                  "initial mass guess / vehicle.yaml mass")
      ->capture_default_str()->check(CLI::Range(0.1, 10.0));
  cmd->add_option("--sigma-q", o->settings.sigma_q, "attitude noise [rad]")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--sigma-p", o->settings.sigma_p, "position noise [m]")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--sigma-v", o->settings.sigma_v, "velocity noise [m/s]")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->callback([o, exit_code]() { *exit_code = run_from_sequence(*o); });
}

}  // namespace vid::massid_app
