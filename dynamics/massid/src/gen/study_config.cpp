/// @file study_config.cpp
/// @brief study.yaml <-> GeneratorSettings. One table of (section, key, field) drives both
/// reading and writing, so the two cannot drift apart.
#include "massid/gen/study_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <variant>

#include "io/errors.h"
#include "io/strict_yaml.h"

namespace vid::massid::gen {
namespace {

using FieldPtr = std::variant<double*, int*, std::uint64_t*, std::vector<double>*,
                              std::vector<std::string>*>;
struct Field {
  std::string section;  ///< "" = top level
  std::string key;
  FieldPtr ptr;
};

std::vector<Field> fields_of(GeneratorSettings& s) {
  TrajectorySettings& t = s.trajectory;
  MassProfileSettings& m = s.mass;
  ControllerSettings& c = s.controller;
  return {
      {"", "trajectories", &s.trajectories}, {"", "profiles", &s.profiles},
      {"", "runs", &s.runs}, {"", "seed", &s.seed}, {"", "rate_hz", &s.rate_hz},
      {"", "duration_s", &s.duration_s}, {"", "integration_substeps", &s.integration_substeps},
      {"", "gravity", &s.gravity}, {"", "mass_min_kg", &s.mass_min_kg},
      {"", "mass_max_kg", &s.mass_max_kg}, {"", "initial_mass_factor", &s.initial_mass_factor},
      {"", "sigma_q", &s.sigma_q}, {"", "sigma_p", &s.sigma_p}, {"", "sigma_v", &s.sigma_v},
      {"trajectory", "altitude_m", &t.altitude_m}, {"trajectory", "ramp_s", &t.ramp_s},
      {"trajectory", "loop_radius_m", &t.loop_radius_m},
      {"trajectory", "loop_period_s", &t.loop_period_s},
      {"trajectory", "loop_z_amplitude_m", &t.loop_z_amplitude_m},
      {"trajectory", "lemniscate_size_m", &t.lemniscate_size_m},
      {"trajectory", "lemniscate_period_s", &t.lemniscate_period_s},
      {"trajectory", "zigzag_dx_m", &t.zigzag_dx_m}, {"trajectory", "zigzag_dy_m", &t.zigzag_dy_m},
      {"trajectory", "zigzag_dz_m", &t.zigzag_dz_m},
      {"trajectory", "zigzag_leg_s", &t.zigzag_leg_s},
      {"trajectory", "square_side_m", &t.square_side_m},
      {"trajectory", "square_leg_s", &t.square_leg_s},
      {"trajectory", "random_accel_xy", &t.random_accel_xy},
      {"trajectory", "random_accel_z", &t.random_accel_z},
      {"trajectory", "random_amplitude_xy", &t.random_amplitude_xy},
      {"trajectory", "random_amplitude_z", &t.random_amplitude_z},
      {"trajectory", "random_freq_min_hz", &t.random_freq_min_hz},
      {"trajectory", "random_freq_max_hz", &t.random_freq_max_hz},
      {"mass", "time_jitter_s", &m.time_jitter_s},
      {"mass", "decrease_start_s", &m.decrease_start_s},
      {"mass", "decrease_end_s", &m.decrease_end_s},
      {"mass", "decrease_fraction", &m.decrease_fraction},
      {"mass", "step_time_s", &m.step_time_s}, {"mass", "step_fraction", &m.step_fraction},
      {"mass", "up_down_times_s", &m.up_down_times_s},
      {"mass", "up_down_fraction", &m.up_down_fraction},
      {"controller", "mpc_dt_s", &c.mpc_dt_s}, {"controller", "horizon", &c.horizon},
      {"controller", "weight_p", &c.weight_p}, {"controller", "weight_v", &c.weight_v},
      {"controller", "weight_a", &c.weight_a}, {"controller", "accel_xy_max", &c.accel_xy_max},
      {"controller", "integral_gain", &c.integral_gain},
      {"controller", "integral_accel_max", &c.integral_accel_max},
      {"controller", "attitude_gain", &c.attitude_gain}, {"controller", "rate_max", &c.rate_max},
      {"controller", "tilt_max_deg", &c.tilt_max_deg},
      {"controller", "thrust_min_ratio", &c.thrust_min_ratio},
      {"controller", "thrust_max_ratio", &c.thrust_max_ratio},
  };
}

/// @brief Read field @p f from its section @p m when present (missing keys keep defaults).
void read_field(const io::YamlMap& m, const Field& f) {
  if (!m.has(f.key)) return;
  std::visit(
      [&](auto* p) {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, double>) {
          *p = m.get_double(f.key);
        } else if constexpr (std::is_same_v<T, int>) {
          *p = m.get_int(f.key);
        } else if constexpr (std::is_same_v<T, std::uint64_t>) {
          *p = m.get_u64(f.key);
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          *p = m.get_doubles(f.key);
        } else {
          *p = m.get_strings(f.key);
        }
      },
      f.ptr);
}

/// @brief Unknown keys keep this reader's "FILE: key 'k': unknown key" message (pinned by tests).
void check_unknown_keys(const io::YamlMap& m) {
  if (const auto k = m.first_unknown()) throw io::ConfigError(m.file() + ": key '" + *k + "': unknown key");
}

}  // namespace

GeneratorSettings parse_generator_settings(const std::string& yaml_text,
                                           const std::string& source) {
  const io::YamlMap root = io::YamlMap::from_node(io::YamlMap::parse_string(yaml_text, source), source, "");
  GeneratorSettings s;
  const std::vector<Field> fields = fields_of(s);
  std::map<std::string, io::YamlMap> sections = {{"", root}};  // "" = top level
  for (const std::string name : {"trajectory", "mass", "controller"}) {
    sections.emplace(name, root.get_map_or_empty(name));
  }
  for (const Field& f : fields) sections.at(f.section).accept(f.key);
  for (const auto& kv : sections) check_unknown_keys(kv.second);  // before any type error
  for (const Field& f : fields) read_field(sections.at(f.section), f);
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    throw io::ConfigError(source + ": " + e.what());
  }
  return s;
}

GeneratorSettings load_generator_settings(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open settings file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_generator_settings(ss.str(), file.string());
}

std::string generator_settings_yaml(const GeneratorSettings& settings) {
  GeneratorSettings copy = settings;
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  std::string open_section;
  for (const Field& f : fields_of(copy)) {
    if (f.section != open_section) {
      if (!open_section.empty()) out << YAML::EndMap;
      out << YAML::Key << f.section << YAML::Value << YAML::BeginMap;
      open_section = f.section;
    }
    out << YAML::Key << f.key << YAML::Value;
    std::visit(
        [&](auto* p) {
          using T = std::remove_pointer_t<decltype(p)>;
          if constexpr (std::is_same_v<T, std::vector<double>> ||
                        std::is_same_v<T, std::vector<std::string>>) {
            out << YAML::Flow << *p;
          } else {
            out << *p;
          }
        },
        f.ptr);
  }
  if (!open_section.empty()) out << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

bool operator==(const GeneratorSettings& a_in, const GeneratorSettings& b_in) {
  GeneratorSettings a = a_in, b = b_in;  // fields_of hands out member pointers of a mutable struct
  const std::vector<Field> fa = fields_of(a), fb = fields_of(b);
  for (std::size_t i = 0; i < fa.size(); ++i) {
    const bool same = std::visit(
        [&](auto* p) { return *p == *std::get<decltype(p)>(fb[i].ptr); }, fa[i].ptr);
    if (!same) return false;
  }
  return true;
}

void validate(const GeneratorSettings& s) {
  static const std::set<std::string> kTraj = {"random", "loop", "lemniscate", "zigzag", "square"};
  static const std::set<std::string> kProf = {"constant", "linear_decrease", "step_drop",
                                              "step_pickup", "up_down"};
  auto bad = [](const std::string& key, const std::string& msg) {
    throw std::invalid_argument("key '" + key + "': " + msg);
  };
  if (s.trajectories.empty()) bad("trajectories", "empty list");
  for (const auto& t : s.trajectories) {
    if (!kTraj.count(t)) bad("trajectories", "unknown trajectory '" + t + "'");
  }
  if (s.profiles.empty()) bad("profiles", "empty list");
  for (const auto& p : s.profiles) {
    if (!kProf.count(p)) bad("profiles", "unknown mass profile '" + p + "'");
  }
  if (s.runs < 1 || s.runs > 999) bad("runs", "must be in [1, 999]");
  if (!(s.rate_hz > 0.0)) bad("rate_hz", "must be positive");
  if (!(s.duration_s > 0.0)) bad("duration_s", "must be positive");
  if (s.integration_substeps < 1) bad("integration_substeps", "must be >= 1");
  if (!(s.gravity > 0.0)) bad("gravity", "must be positive");
  if (!(s.mass_min_kg > 0.0 && s.mass_max_kg >= s.mass_min_kg)) {
    bad("mass_max_kg", "need 0 < mass_min_kg <= mass_max_kg");
  }
  if (!(s.initial_mass_factor > 0.0)) bad("initial_mass_factor", "must be positive");
  if (!(s.sigma_q >= 0.0)) bad("sigma_q", "must be >= 0");
  if (!(s.sigma_p >= 0.0)) bad("sigma_p", "must be >= 0");
  if (!(s.sigma_v >= 0.0)) bad("sigma_v", "must be >= 0");
  const ControllerSettings& c = s.controller;
  if (c.horizon < 1 || c.horizon > 100) bad("controller.horizon", "must be in [1, 100]");
  if (!(c.mpc_dt_s > 0.0)) bad("controller.mpc_dt_s", "must be positive");
  if (!(c.weight_a > 0.0)) bad("controller.weight_a", "must be positive (keeps the QP convex)");
  if (!(c.thrust_max_ratio > c.thrust_min_ratio && c.thrust_min_ratio >= 0.0)) {
    bad("controller.thrust_max_ratio", "need 0 <= thrust_min_ratio < thrust_max_ratio");
  }
  if (!(c.tilt_max_deg > 0.0 && c.tilt_max_deg < 89.0)) {
    bad("controller.tilt_max_deg", "must be in (0, 89)");
  }
  if (!(c.rate_max > 0.0)) bad("controller.rate_max", "must be positive");
  const MassProfileSettings& m = s.mass;
  if (!(m.decrease_end_s > m.decrease_start_s)) {
    bad("mass.decrease_end_s", "must be after decrease_start_s");
  }
  if (!(m.decrease_fraction >= 0.0 && m.decrease_fraction < 1.0)) {
    bad("mass.decrease_fraction", "must be in [0, 1)");
  }
  if (!(m.step_fraction >= 0.0 && m.step_fraction < 1.0)) bad("mass.step_fraction", "must be in [0, 1)");
  if (!std::is_sorted(m.up_down_times_s.begin(), m.up_down_times_s.end())) {
    bad("mass.up_down_times_s", "must be increasing");
  }
  if (!(s.trajectory.random_freq_max_hz >= s.trajectory.random_freq_min_hz &&
        s.trajectory.random_freq_min_hz > 0.0)) {
    bad("trajectory.random_freq_max_hz", "need 0 < random_freq_min_hz <= random_freq_max_hz");
  }
}

}  // namespace vid::massid::gen
