#pragma once
/// @file yaml_fields.h
/// @brief Strict YAML field readers for the render/scene/feature config sections (private).
/// Every error names the file, the line and the full key path.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <initializer_list>
#include <string>

#include "io/errors.h"

namespace vid::sim::detail {

/// @brief A YAML map being read: file name and dotted key prefix for messages.
class YamlMap {
 public:
  YamlMap(const YAML::Node& node, std::string file, std::string path);

  /// @brief Throw if the map has a key outside `allowed`.
  void allow_only(std::initializer_list<const char*> allowed) const;
  /// @brief True if `key` is present.
  bool has(const char* key) const;
  /// @brief Child map (must be a map).
  YamlMap child(const char* key) const;

  /// @brief Optional readers: leave `*out` unchanged when the key is missing.
  void read(const char* key, double* out) const;
  void read(const char* key, int* out) const;
  void read(const char* key, std::uint64_t* out) const;
  void read(const char* key, bool* out) const;
  void read(const char* key, std::string* out) const;
  void read(const char* key, Eigen::Vector2d* out) const;
  void read(const char* key, Eigen::Vector3d* out) const;

  /// @brief Error "FILE:LINE: key 'path.key': msg" as ConfigError.
  [[noreturn]] void fail(const char* key, const std::string& msg) const;
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

 private:
  YAML::Node get(const char* key) const;
  template <int N>
  void read_vec(const char* key, Eigen::Matrix<double, N, 1>* out) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
};

}  // namespace vid::sim::detail
