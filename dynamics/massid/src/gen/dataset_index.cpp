/// @file dataset_index.cpp
/// @brief manifest.yaml writer/reader and the run file layout of a study dataset.
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "massid/gen/manifest.h"
#include "massid/run_data.h"

namespace vid::massid {
namespace {

constexpr const char* kFormat = "vid_massid_dataset";
constexpr int kVersion = 1;

[[noreturn]] void key_error(const std::filesystem::path& file, const std::string& key,
                            const std::string& msg) {
  throw std::runtime_error(file.string() + ": key '" + key + "': " + msg);
}

template <typename T>
T get(const YAML::Node& map, const std::string& key, const std::filesystem::path& file,
      const std::string& where) {
  const YAML::Node n = map[key];
  if (!n) key_error(file, where + key, "missing");
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    key_error(file, where + key, "wrong type");
  }
}

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
                                                     : YAML::Load(generator_yaml);
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
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(file.string() + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap()) throw std::runtime_error(file.string() + ": top level must be a map");
  if (get<std::string>(root, "format", file, "") != kFormat) {
    key_error(file, "format", std::string("expected '") + kFormat + "'");
  }
  if (get<int>(root, "version", file, "") != kVersion) {
    key_error(file, "version", "unsupported version (expected " + std::to_string(kVersion) + ")");
  }
  const YAML::Node runs = root["runs"];
  if (!runs || !runs.IsSequence()) key_error(file, "runs", "missing or not a list");
  DatasetIndex index;
  index.root = dir;
  for (size_t i = 0; i < runs.size(); ++i) {
    const YAML::Node r = runs[i];
    const std::string where = "runs[" + std::to_string(i) + "].";
    if (!r.IsMap()) key_error(file, "runs[" + std::to_string(i) + "]", "not a map");
    RunInfo info;
    info.trajectory = get<std::string>(r, "trajectory", file, where);
    info.mass_profile = get<std::string>(r, "mass_profile", file, where);
    info.index = get<int>(r, "index", file, where);
    info.seed = get<std::uint64_t>(r, "seed", file, where);
    info.gravity = get<double>(r, "gravity", file, where);
    info.initial_mass_guess = get<double>(r, "initial_mass_guess", file, where);
    info.sigma_q = get<double>(r, "sigma_q", file, where);
    info.sigma_p = get<double>(r, "sigma_p", file, where);
    info.sigma_v = get<double>(r, "sigma_v", file, where);
    if (info.index < 0) key_error(file, where + "index", "must be >= 0");
    if (!(info.initial_mass_guess > 0.0)) key_error(file, where + "initial_mass_guess", "must be > 0");
    if (!(info.gravity > 0.0)) key_error(file, where + "gravity", "must be > 0");
    index.runs.push_back(info);
  }
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
