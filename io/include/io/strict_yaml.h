#pragma once
/// @file strict_yaml.h
/// @brief Strict, typed access to YAML configuration files (yaml-cpp underneath).
///
/// Every read marks its key as consumed; check_unknown() then rejects keys nobody read, so a
/// typo in a config never passes silently. Messages name the file, line and full key path:
///   "FILE:LINE: unknown key 'cam0.intrinsic'"
///   "FILE: missing required key 'cam0.intrinsics'"
///   "FILE:LINE: key 'imu0.update_rate': expected a number, got 'fast'"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
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

  /// @brief True if the key exists (does not consume it).
  bool has(const std::string& key) const;
  /// @brief Keys of this map in file order.
  std::vector<std::string> keys() const;

  double get_double(const std::string& key) const;
  double get_double(const std::string& key, double fallback) const;
  int get_int(const std::string& key) const;
  int get_int(const std::string& key, int fallback) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  /// @brief A flow/block sequence of numbers; @p size < 0 accepts any length.
  std::vector<double> get_doubles(const std::string& key, int size = -1) const;
  std::vector<int> get_ints(const std::string& key, int size = -1) const;
  /// @brief A 4x4 matrix: Kalibr's nested list [[..],[..],[..],[..]] or EuRoC/OpenCV's
  /// {rows: 4, cols: 4, data: [16 numbers row-major]} (optional dt: d).
  Eigen::Matrix4d get_matrix4(const std::string& key) const;
  /// @brief A nested mapping (its keys are checked by its own check_unknown()).
  YamlMap get_map(const std::string& key) const;
  /// @brief Mark a known key as accepted without reading it (e.g. Kalibr's rostopic).
  void accept(const std::string& key) const;

  /// @brief Throw ConfigError for the first key that was never read or accepted.
  void check_unknown() const;
  /// @brief Throw ConfigError "FILE:LINE: key 'path.key': message".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  const std::string& file() const { return file_; }
  /// @brief Full dotted path of @p key in this file ("cam0.intrinsics").
  std::string full_key(const std::string& key) const;

 private:
  YamlMap(YAML::Node node, std::string file, std::string prefix);
  YAML::Node require(const std::string& key) const;
  YAML::Node find(const std::string& key) const;
  double to_double(const YAML::Node& n, const std::string& key) const;
  int to_int(const YAML::Node& n, const std::string& key) const;
  int line_of(const YAML::Node& n) const;

  YAML::Node node_;
  std::string file_;
  std::string prefix_;
  std::shared_ptr<std::set<std::string>> consumed_;
};

}  // namespace vid::io
