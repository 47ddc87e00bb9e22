#include "yaml_section.h"

#include <Eigen/LU>

#include "io/errors.h"

namespace vid::sim::detail {

YamlSection::YamlSection(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    throw io::ConfigError(file_ + ": key '" + (path_.empty() ? std::string("<root>") : path_) +
                          "': expected a mapping");
  }
}

void YamlSection::fail(const std::string& key, const std::string& message) const {
  throw io::ConfigError(file_ + ": key '" + full(key) + "': " + message);
}

bool YamlSection::has(const std::string& key) const {
  return node_ && node_.IsMap() && node_[key] && !node_[key].IsNull();
}

std::optional<YAML::Node> YamlSection::get(const std::string& key) const {
  read_.insert(key);
  if (!has(key)) return std::nullopt;
  return node_[key];
}

double YamlSection::num(const std::string& key) const {
  if (!has(key)) fail(key, "missing required key");
  return num(key, 0.0);
}

double YamlSection::num(const std::string& key, double fallback) const {
  const std::optional<YAML::Node> on = get(key);
  if (!on) return fallback;
  const YAML::Node& n = *on;
  try {
    if (!n.IsScalar()) fail(key, "expected a number");
    return n.as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a number, got '" + n.Scalar() + "'");
  }
}

int YamlSection::integer(const std::string& key, int fallback) const {
  const std::optional<YAML::Node> on = get(key);
  if (!on) return fallback;
  const YAML::Node& n = *on;
  try {
    return n.as<int>();
  } catch (const YAML::Exception&) {
    fail(key, "expected an integer");
  }
}

std::uint64_t YamlSection::u64(const std::string& key, std::uint64_t fallback) const {
  const std::optional<YAML::Node> on = get(key);
  if (!on) return fallback;
  const YAML::Node& n = *on;
  try {
    return n.as<std::uint64_t>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a non-negative integer");
  }
}

bool YamlSection::flag(const std::string& key, bool fallback) const {
  const std::optional<YAML::Node> on = get(key);
  if (!on) return fallback;
  const YAML::Node& n = *on;
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    fail(key, "expected true or false");
  }
}

std::string YamlSection::str(const std::string& key, const std::string& fallback) const {
  const std::optional<YAML::Node> on = get(key);
  if (!on) return fallback;
  const YAML::Node& n = *on;
  if (!n.IsScalar()) fail(key, "expected a string");
  return n.Scalar();
}

std::vector<double> YamlSection::nums(const std::string& key, int size) const {
  const std::optional<YAML::Node> on = get(key);
  if (!on) fail(key, "missing required key");
  const YAML::Node& n = *on;
  if (!n.IsSequence()) fail(key, "expected a list of numbers");
  if (size >= 0 && static_cast<int>(n.size()) != size)
    fail(key, "expected " + std::to_string(size) + " numbers, got " + std::to_string(n.size()));
  std::vector<double> out;
  for (const auto& e : n) {
    try {
      out.push_back(e.as<double>());
    } catch (const YAML::Exception&) {
      fail(key, "expected a list of numbers");
    }
  }
  return out;
}

Eigen::Vector3d YamlSection::vec3(const std::string& key, const Eigen::Vector3d& fallback) const {
  if (!has(key)) {
    read_.insert(key);
    return fallback;
  }
  const auto v = nums(key, 3);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Eigen::Matrix4d YamlSection::mat4(const std::string& key) const {
  const std::optional<YAML::Node> on = get(key);
  if (!on) fail(key, "missing required key");
  const YAML::Node& n = *on;
  Eigen::Matrix4d T;
  try {
    if (n.IsSequence()) {
      if (n.size() != 4) fail(key, "expected 4 rows");
      for (int r = 0; r < 4; ++r) {
        if (!n[r].IsSequence() || n[r].size() != 4) fail(key, "expected 4x4 numbers");
        for (int c = 0; c < 4; ++c) T(r, c) = n[r][c].as<double>();
      }
    } else if (n.IsMap()) {
      YamlSection m(n, file_, full(key));
      if (m.integer("rows", 4) != 4 || m.integer("cols", 4) != 4) fail(key, "expected rows: 4, cols: 4");
      const auto d = m.nums("data", 16);
      m.finish();
      for (int i = 0; i < 16; ++i) T(i / 4, i % 4) = d[static_cast<std::size_t>(i)];
    } else {
      fail(key, "expected a 4x4 matrix");
    }
  } catch (const YAML::Exception&) {
    fail(key, "expected a 4x4 matrix of numbers");
  }
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) fail(key, "last row must be [0, 0, 0, 1]");
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0)
    fail(key, "rotation part is not a rotation matrix");
  return T;
}

YamlSection YamlSection::sub(const std::string& key) const {
  const std::optional<YAML::Node> on = get(key);
  return YamlSection(on ? *on : YAML::Node(YAML::NodeType::Map), file_, full(key));
}

std::vector<YamlSection> YamlSection::list(const std::string& key) const {
  const std::optional<YAML::Node> on = get(key);
  std::vector<YamlSection> out;
  if (!on) return out;
  const YAML::Node& n = *on;
  if (!n.IsSequence()) fail(key, "expected a list");
  for (std::size_t i = 0; i < n.size(); ++i) out.emplace_back(n[i], file_, full(key) + "[" + std::to_string(i) + "]");
  return out;
}

YAML::Node YamlSection::raw(const std::string& key) const {
  const std::optional<YAML::Node> on = get(key);
  return on ? *on : YAML::Node();
}

void YamlSection::finish() const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string k = kv.first.Scalar();
    if (!read_.count(k)) fail(k, "unknown key");
  }
}

}  // namespace vid::sim::detail
