/// @file dataset_index.cpp
/// @brief manifest.yaml writer/reader and the run file layout of a study dataset.
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "io/strict_yaml.h"
#include "massid/gen/manifest.h"
#include "massid/run_data.h"

namespace vid::massid {
namespace {

constexpr const char* kFormat = "vid_massid_dataset";
constexpr int kVersion = 1;

}  // namespace

namespace gen {

void write_manifest(const std::filesystem::path& dir, const std::string& generator_yaml,
                    const std::vector<RunInfo>& runs) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << kFormat;
  out << YAML::Key << "version" << YAML::Value << kVersion;
  out << YAML::Key << "generator" << YAML::Value;
  const YAML::Node gen_node = generator_yaml.empty() ? YAML::Node(YAML::NodeType::Map)
                                                     : io::YamlMap::parse_string(generator_yaml, "generator settings");
  out << gen_node;
  out << YAML::Key << "runs" << YAML::Value << YAML::BeginSeq;
  for (const RunInfo& r : runs) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "trajectory" << YAML::Value << r.trajectory;
    out << YAML::Key << "mass_profile" << YAML::Value << r.mass_profile;
    out << YAML::Key << "index" << YAML::Value << r.index;
    out << YAML::Key << "seed" << YAML::Value << r.seed;
    out << YAML::Key << "gravity" << YAML::Value << r.gravity;
    out << YAML::Key << "initial_mass_guess" << YAML::Value << r.initial_mass_guess;
    out << YAML::Key << "sigma_q" << YAML::Value << r.sigma_q;
    out << YAML::Key << "sigma_p" << YAML::Value << r.sigma_p;
    out << YAML::Key << "sigma_v" << YAML::Value << r.sigma_v;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  const std::filesystem::path file = dir / "manifest.yaml";
  std::ofstream f(file, std::ios::trunc);
  if (!f) throw std::runtime_error(file.string() + ": cannot open for writing");
  f << out.c_str() << "\n";
  f.close();
  if (!f) throw std::runtime_error(file.string() + ": write failed");
}

}  // namespace gen

DatasetIndex read_dataset_index(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "manifest.yaml";
  if (!std::filesystem::exists(file)) {
    throw std::runtime_error(file.string() + ": no manifest (not a vid_massid dataset folder)");
  }
  const io::YamlMap root = io::YamlMap::load_file(file);
  if (root.get_string("format") != kFormat) root.fail("format", std::string("expected '") + kFormat + "'");
  if (root.get_int("version") != kVersion) {
    root.fail("version", "unsupported version (expected " + std::to_string(kVersion) + ")");
  }
  root.accept("generator");  // the study settings, for the record; the runs below are what counts
  if (!root.has("runs")) root.fail("runs", "missing list of runs");
  DatasetIndex index;
  index.root = dir;
  for (const io::YamlMap& r : root.get_maps("runs")) {
    RunInfo info;
    info.trajectory = r.get_string("trajectory");
    info.mass_profile = r.get_string("mass_profile");
    info.index = r.get_int("index");
    info.seed = r.get_u64("seed");
    info.gravity = r.get_double("gravity");
    info.initial_mass_guess = r.get_double("initial_mass_guess");
    info.sigma_q = r.get_double("sigma_q");
    info.sigma_p = r.get_double("sigma_p");
    info.sigma_v = r.get_double("sigma_v");
    r.check_unknown();
    if (info.index < 0) r.fail("index", "must be >= 0");
    if (!(info.initial_mass_guess > 0.0)) r.fail("initial_mass_guess", "must be > 0");
    if (!(info.gravity > 0.0)) r.fail("gravity", "must be > 0");
    index.runs.push_back(info);
  }
  root.check_unknown();
  return index;
}

std::filesystem::path run_csv_path(const std::filesystem::path& root, const RunInfo& info) {
  char name[32];
  std::snprintf(name, sizeof(name), "run_%03d.csv", info.index);
  return root / info.trajectory / info.mass_profile / name;
}

MassIdRun load_run(const DatasetIndex& index, const RunInfo& info) {
  MassIdRun run;
  run.info = info;
  run.samples = read_run_csv(run_csv_path(index.root, info));
  return run;
}

}  // namespace vid::massid
