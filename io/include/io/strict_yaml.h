#pragma once
/// @file strict_yaml.h
/// @brief Strict, typed access to YAML configuration files (yaml-cpp underneath).
///
/// Every read marks its key as consumed; check_unknown() then rejects keys nobody read, so a
/// typo in a config never passes silently. A key with an empty value (`key:` or `key: ~`)
/// counts as absent. This is the one YAML reader of the project (io, sim, render, massid, LCM). Messages name the file, line and full key path:
///   "FILE:LINE: unknown key 'cam0.intrinsic'"
///   "FILE: missing required key 'cam0.intrinsics'"
///   "FILE:LINE: key 'imu0.update_rate': expected a number, got 'fast'"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "io/errors.h"

namespace vid::io {

/// @brief A YAML mapping of one file, with consumed-key tracking.
class YamlMap {
 public:
  /// @brief Load a file whose root is a mapping. Accepts OpenCV's "%YAML:1.0" first line.
  /// Throws ConfigError for a missing file, a syntax error (with line) or a non-map root.
  static YamlMap load_file(const std::filesystem::path& path);
  /// @brief Parse @p text; @p name stands for the file in messages.
  static YamlMap load_string(const std::string& text, const std::string& name);
  /// @brief Wrap an already parsed node (e.g. a merged scenario) whose keys print as
  /// "prefix.key"; a null/undefined node is an empty map, any other non-map throws.
  static YamlMap from_node(const YAML::Node& node, const std::string& file, const std::string& prefix);
  /// @brief Parse a whole file into a node (same syntax-error messages as load_file).
  static YAML::Node parse_file(const std::filesystem::path& path);
  /// @brief Parse text into a node; @p name stands for the file in messages. A key given twice
  /// in one mapping is an error naming its line (yaml-cpp would silently keep the first).
  static YAML::Node parse_string(const std::string& text, const std::string& name);

  /// @brief True if the key exists with a non-empty value (does not consume it).
  bool has(const std::string& key) const;
  /// @brief Keys of this map in file order.
  std::vector<std::string> keys() const;

  double get_double(const std::string& key) const;
  double get_double(const std::string& key, double fallback) const;
  int get_int(const std::string& key) const;
  int get_int(const std::string& key, int fallback) const;
  /// @brief A non-negative 64-bit integer (seeds).
  std::uint64_t get_u64(const std::string& key) const;
  std::uint64_t get_u64(const std::string& key, std::uint64_t fallback) const;
  bool get_bool(const std::string& key) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  /// @brief A flow/block sequence of numbers; @p size < 0 accepts any length.
  std::vector<double> get_doubles(const std::string& key, int size = -1) const;
  std::vector<int> get_ints(const std::string& key, int size = -1) const;
  /// @brief A list of strings (any length).
  std::vector<std::string> get_strings(const std::string& key) const;
  /// @brief A list of exactly 2 / 3 numbers.
  Eigen::Vector2d get_vec2(const std::string& key, const Eigen::Vector2d& fallback) const;
  Eigen::Vector3d get_vec3(const std::string& key) const;
  Eigen::Vector3d get_vec3(const std::string& key, const Eigen::Vector3d& fallback) const;
  /// @brief A 4x4 matrix: Kalibr's nested list [[..],[..],[..],[..]] or EuRoC/OpenCV's
  /// {rows: 4, cols: 4, data: [16 numbers row-major]} (optional dt: d).
  Eigen::Matrix4d get_matrix4(const std::string& key) const;
  /// @brief A nested mapping (its keys are checked by its own check_unknown()).
  YamlMap get_map(const std::string& key) const;
  /// @brief Like get_map, but a missing key gives an empty map (all defaults).
  YamlMap get_map_or_empty(const std::string& key) const;
  /// @brief A list of mappings (missing -> empty); item i prints as "key[i].sub".
  std::vector<YamlMap> get_maps(const std::string& key) const;
  /// @brief The raw node of @p key, marked as read (its contents are checked elsewhere);
  /// an undefined node when missing.
  YAML::Node get_raw(const std::string& key) const;
  /// @brief 1-based line of @p key's value, or 0 when unknown/missing.
  int line(const std::string& key) const;
  /// @brief Mark a known key as accepted without reading it (e.g. Kalibr's rostopic).
  void accept(const std::string& key) const;

  /// @brief Throw ConfigError "FILE:LINE: unknown key 'path.key'" for the first key that was
  /// never read or accepted.
  void check_unknown() const;
  /// @brief Full path of the first key never read or accepted (for readers whose message
  /// format is fixed by their tests), or nullopt.
  std::optional<std::string> first_unknown() const;
  /// @brief Throw ConfigError "FILE:LINE: key 'path.key': message".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  const std::string& file() const { return file_; }
  /// @brief Full dotted path of @p key in this file ("cam0.intrinsics").
  std::string full_key(const std::string& key) const;

 private:
  YamlMap(YAML::Node node, std::string file, std::string prefix);
  YAML::Node require(const std::string& key) const;
  /// @brief has(key); an absent/empty key is marked read (fallback getters use this).
  bool present(const std::string& key) const;
  YAML::Node find(const std::string& key) const;
  double to_double(const YAML::Node& n, const std::string& key) const;
  int to_int(const YAML::Node& n, const std::string& key) const;
  std::uint64_t to_u64(const YAML::Node& n, const std::string& key) const;
  int line_of(const YAML::Node& n) const;

  YAML::Node node_;
  std::string file_;
  std::string prefix_;
  std::shared_ptr<std::set<std::string>> consumed_;
};

}  // namespace vid::io
