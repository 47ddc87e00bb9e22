#pragma once
/// @file yaml_section.h
/// @brief Strict typed access to one YAML mapping of a scenario file: every read key is
/// remembered and finish() rejects the rest. Errors are vid::io::ConfigError
/// "FILE: key 'a.b.c': message". Private to sim.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace vid::sim::detail {

class YamlSection {
 public:
  YamlSection(YAML::Node node, std::string file, std::string path);
  bool has(const std::string& key) const;
  double num(const std::string& key, double fallback) const;
  double num(const std::string& key) const;
  int integer(const std::string& key, int fallback) const;
  std::uint64_t u64(const std::string& key, std::uint64_t fallback) const;
  bool flag(const std::string& key, bool fallback) const;
  std::string str(const std::string& key, const std::string& fallback) const;
  std::vector<double> nums(const std::string& key, int size = -1) const;
  Eigen::Vector3d vec3(const std::string& key, const Eigen::Vector3d& fallback) const;
  /// @brief 4x4 matrix as a nested list [[...], x4] or {rows, cols, data}.
  Eigen::Matrix4d mat4(const std::string& key) const;
  /// @brief Nested mapping (missing -> empty section).
  YamlSection sub(const std::string& key) const;
  /// @brief Sequence of mappings.
  std::vector<YamlSection> list(const std::string& key) const;
  /// @brief Raw node (marks the key as read; its contents are checked elsewhere).
  YAML::Node raw(const std::string& key) const;
  /// @brief Throw for the first key that was never read.
  void finish() const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  std::string full(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& file() const { return file_; }

 private:
  std::optional<YAML::Node> get(const std::string& key) const;
  YAML::Node node_;
  std::string file_;
  std::string path_;
  mutable std::set<std::string> read_;
};

}  // namespace vid::sim::detail
