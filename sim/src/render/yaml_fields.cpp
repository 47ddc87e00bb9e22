#include "yaml_fields.h"

#include <algorithm>
#include <cstring>

namespace vid::sim::detail {

namespace {
std::string where(const std::string& file, const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  if (m.line >= 0) return file + ":" + std::to_string(m.line + 1);
  return file;
}
}  // namespace

YamlMap::YamlMap(const YAML::Node& node, std::string file, std::string path)
    : node_(node), file_(std::move(file)), path_(std::move(path)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    throw io::ConfigError(where(file_, node_) + ": key '" + path_ + "': expected a map");
  }
}

void YamlMap::fail(const char* key, const std::string& msg) const {
  const std::string full = key ? path_ + "." + key : path_;
  YAML::Node n = (key && has(key)) ? get(key) : node_;
  throw io::ConfigError(where(file_, n) + ": key '" + full + "': " + msg);
}

void YamlMap::allow_only(std::initializer_list<const char*> allowed) const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string k = kv.first.as<std::string>();
    const bool ok = std::any_of(allowed.begin(), allowed.end(),
                                [&](const char* a) { return k == a; });
    if (!ok) {
      throw io::ConfigError(where(file_, kv.first) + ": key '" + path_ + "." + k +
                            "': unknown key");
    }
  }
}

bool YamlMap::has(const char* key) const {
  return node_ && node_.IsMap() && static_cast<bool>(node_[key]);
}

YAML::Node YamlMap::get(const char* key) const { return node_[key]; }

YamlMap YamlMap::child(const char* key) const {
  YAML::Node n = get(key);
  if (!n.IsMap()) fail(key, "expected a map");
  return YamlMap(n, file_, path_ + "." + key);
}

void YamlMap::read(const char* key, double* out) const {
  if (!has(key)) return;
  try {
    *out = get(key).as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a number");
  }
}

void YamlMap::read(const char* key, int* out) const {
  if (!has(key)) return;
  try {
    *out = get(key).as<int>();
  } catch (const YAML::Exception&) {
    fail(key, "expected an integer");
  }
}

void YamlMap::read(const char* key, std::uint64_t* out) const {
  if (!has(key)) return;
  try {
    const long long v = get(key).as<long long>();
    if (v < 0) fail(key, "expected a non-negative integer");
    *out = static_cast<std::uint64_t>(v);
  } catch (const YAML::Exception&) {
    fail(key, "expected a non-negative integer");
  }
}

void YamlMap::read(const char* key, bool* out) const {
  if (!has(key)) return;
  try {
    *out = get(key).as<bool>();
  } catch (const YAML::Exception&) {
    fail(key, "expected true or false");
  }
}

void YamlMap::read(const char* key, std::string* out) const {
  if (!has(key)) return;
  YAML::Node n = get(key);
  if (!n.IsScalar()) fail(key, "expected a string");
  *out = n.as<std::string>();
}

template <int N>
void YamlMap::read_vec(const char* key, Eigen::Matrix<double, N, 1>* out) const {
  if (!has(key)) return;
  YAML::Node n = get(key);
  if (!n.IsSequence() || n.size() != static_cast<std::size_t>(N)) {
    fail(key, "expected a list of " + std::to_string(N) + " numbers");
  }
  try {
    for (int i = 0; i < N; ++i) (*out)[i] = n[i].as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a list of " + std::to_string(N) + " numbers");
  }
}

void YamlMap::read(const char* key, Eigen::Vector2d* out) const { read_vec<2>(key, out); }
void YamlMap::read(const char* key, Eigen::Vector3d* out) const { read_vec<3>(key, out); }

}  // namespace vid::sim::detail
