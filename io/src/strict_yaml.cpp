#include "io/strict_yaml.h"

#include <charconv>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace vid::io {
namespace {

std::string scalar_text(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a sequence";
  if (n.IsMap()) return "a mapping";
  return "nothing";
}

/// yaml-cpp accepts a key twice in one mapping and its lookups return the first value, so a
/// setting appended to override an earlier one would be ignored without a word: reject it.
void reject_duplicate_keys(const YAML::Node& node, const std::string& name) {
  if (node.IsSequence()) {
    for (const auto& child : node) reject_duplicate_keys(child, name);
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> first_line;
  for (const auto& kv : node) {
    if (kv.first.IsScalar()) {
      const int line = kv.first.Mark().line + 1;
      const auto [it, inserted] = first_line.emplace(kv.first.Scalar(), line);
      if (!inserted) {
        throw ConfigError(name + ":" + std::to_string(line) + ": key '" + kv.first.Scalar() +
                          "': given twice (first at line " + std::to_string(it->second) + ")");
      }
    }
    reject_duplicate_keys(kv.second, name);
  }
}

}  // namespace

YamlMap::YamlMap(YAML::Node node, std::string file, std::string prefix)
    : node_(std::move(node)),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      consumed_(std::make_shared<std::set<std::string>>()) {}

YAML::Node YamlMap::parse_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path.string() + ": missing file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_string(ss.str(), path.string());
}

YAML::Node YamlMap::parse_string(const std::string& text_in, const std::string& name) {
  std::string text = text_in;
  // OpenCV FileStorage copies start with "%YAML:1.0", which is not valid YAML: blank that
  // line (keeping line numbers) so the rest parses as plain YAML.
  if (text.rfind("%YAML", 0) == 0) {
    const std::size_t eol = text.find('\n');
    text = std::string("\n") + (eol == std::string::npos ? "" : text.substr(eol + 1));
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  reject_duplicate_keys(root, name);
  return root;
}

YamlMap YamlMap::load_file(const std::filesystem::path& path) {
  const YAML::Node root = parse_file(path);
  if (!root.IsMap()) throw ConfigError(path.string() + ": empty file or not a YAML mapping");
  return YamlMap(root, path.string(), "");
}

YamlMap YamlMap::load_string(const std::string& text, const std::string& name) {
  const YAML::Node root = parse_string(text, name);
  if (!root.IsMap()) throw ConfigError(name + ": empty file or not a YAML mapping");
  return YamlMap(root, name, "");
}

YamlMap YamlMap::from_node(const YAML::Node& node, const std::string& file, const std::string& prefix) {
  if (!node || node.IsNull()) return YamlMap(YAML::Node(YAML::NodeType::Map), file, prefix);
  if (!node.IsMap()) {
    const std::string where = node.Mark().line >= 0 ? file + ":" + std::to_string(node.Mark().line + 1) : file;
    throw ConfigError(where + ": key '" + (prefix.empty() ? std::string("<root>") : prefix) +
                      "': expected a mapping, got " + scalar_text(node));
  }
  return YamlMap(node, file, prefix);
}

std::string YamlMap::full_key(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

int YamlMap::line_of(const YAML::Node& n) const { return n.Mark().line + 1; }

void YamlMap::fail(const std::string& key, const std::string& message) const {
  const int at = line(key);
  const std::string where = at > 0 ? file_ + ":" + std::to_string(at) : file_;
  throw ConfigError(where + ": key '" + full_key(key) + "': " + message);
}

YAML::Node YamlMap::find(const std::string& key) const {
  for (const auto& kv : node_) {
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.second;
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

bool YamlMap::has(const std::string& key) const {
  const YAML::Node n = find(key);
  return n.IsDefined() && !n.IsNull();
}

int YamlMap::line(const std::string& key) const {
  const YAML::Node n = find(key);
  return (n.IsDefined() && n.Mark().line >= 0) ? line_of(n) : 0;
}

std::vector<std::string> YamlMap::keys() const {
  std::vector<std::string> out;
  for (const auto& kv : node_) out.push_back(kv.first.IsScalar() ? kv.first.Scalar() : "?");
  return out;
}

YAML::Node YamlMap::require(const std::string& key) const {
  if (!has(key)) throw ConfigError(file_ + ": missing required key '" + full_key(key) + "'");
  consumed_->insert(key);
  return find(key);
}

void YamlMap::accept(const std::string& key) const { consumed_->insert(key); }

bool YamlMap::present(const std::string& key) const {
  if (has(key)) return true;
  accept(key);  // an empty value of a known key is not an unknown key
  return false;
}

double YamlMap::to_double(const YAML::Node& n, const std::string& key) const {
  if (!n.IsScalar()) fail(key, "expected a number, got " + scalar_text(n));
  std::string_view s = n.Scalar();
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    // YAML spells non-finite numbers .nan / .inf / -.inf (any case).
    std::string lower;
    for (char ch : s) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (lower == ".nan" || lower == ".inf" || lower == "-.inf") {
      fail(key, "expected a finite number, got '" + n.Scalar() + "'");
    }
    fail(key, "expected a number, got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(key, "expected a finite number, got '" + n.Scalar() + "'");
  return v;
}

int YamlMap::to_int(const YAML::Node& n, const std::string& key) const {
  if (!n.IsScalar()) fail(key, "expected an integer, got " + scalar_text(n));
  std::string_view s = n.Scalar();
  if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);
  int v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    fail(key, "expected an integer, got '" + n.Scalar() + "'");
  }
  return v;
}

std::uint64_t YamlMap::to_u64(const YAML::Node& n, const std::string& key) const {
  if (!n.IsScalar()) fail(key, "expected a non-negative integer, got " + scalar_text(n));
  std::string_view s = n.Scalar();
  if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    fail(key, "expected a non-negative integer, got '" + n.Scalar() + "'");
  }
  return v;
}

double YamlMap::get_double(const std::string& key) const { return to_double(require(key), key); }
double YamlMap::get_double(const std::string& key, double fallback) const {
  return present(key) ? get_double(key) : fallback;
}
int YamlMap::get_int(const std::string& key) const { return to_int(require(key), key); }
int YamlMap::get_int(const std::string& key, int fallback) const {
  return present(key) ? get_int(key) : fallback;
}

std::uint64_t YamlMap::get_u64(const std::string& key) const { return to_u64(require(key), key); }
std::uint64_t YamlMap::get_u64(const std::string& key, std::uint64_t fallback) const {
  return present(key) ? get_u64(key) : fallback;
}

bool YamlMap::get_bool(const std::string& key, bool fallback) const {
  return present(key) ? get_bool(key) : fallback;
}

bool YamlMap::get_bool(const std::string& key) const {
  const YAML::Node n = require(key);
  if (n.IsScalar()) {
    const std::string& s = n.Scalar();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
  }
  fail(key, "expected true or false, got " + scalar_text(n));
}

std::string YamlMap::get_string(const std::string& key) const {
  const YAML::Node n = require(key);
  if (!n.IsScalar()) fail(key, "expected a string, got " + scalar_text(n));
  return n.Scalar();
}
std::string YamlMap::get_string(const std::string& key, const std::string& fallback) const {
  return present(key) ? get_string(key) : fallback;
}

std::vector<double> YamlMap::get_doubles(const std::string& key, int size) const {
  const YAML::Node n = require(key);
  if (!n.IsSequence()) fail(key, "expected a list of numbers, got " + scalar_text(n));
  if (size >= 0 && static_cast<int>(n.size()) != size) {
    fail(key, "expected " + std::to_string(size) + " numbers, got " + std::to_string(n.size()));
  }
  std::vector<double> out;
  for (const auto& e : n) out.push_back(to_double(e, key));
  return out;
}

std::vector<int> YamlMap::get_ints(const std::string& key, int size) const {
  const YAML::Node n = require(key);
  if (!n.IsSequence()) fail(key, "expected a list of integers, got " + scalar_text(n));
  if (size >= 0 && static_cast<int>(n.size()) != size) {
    fail(key, "expected " + std::to_string(size) + " integers, got " + std::to_string(n.size()));
  }
  std::vector<int> out;
  for (const auto& e : n) out.push_back(to_int(e, key));
  return out;
}

std::vector<std::string> YamlMap::get_strings(const std::string& key) const {
  const YAML::Node n = require(key);
  if (!n.IsSequence()) fail(key, "expected a list of strings, got " + scalar_text(n));
  std::vector<std::string> out;
  for (const auto& e : n) {
    if (!e.IsScalar()) fail(key, "expected a list of strings, got an element that is " + scalar_text(e));
    out.push_back(e.Scalar());
  }
  return out;
}

Eigen::Vector2d YamlMap::get_vec2(const std::string& key, const Eigen::Vector2d& fallback) const {
  if (!present(key)) return fallback;
  const std::vector<double> v = get_doubles(key, 2);
  return {v[0], v[1]};
}

Eigen::Vector3d YamlMap::get_vec3(const std::string& key) const {
  const std::vector<double> v = get_doubles(key, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Vector3d YamlMap::get_vec3(const std::string& key, const Eigen::Vector3d& fallback) const {
  return present(key) ? get_vec3(key) : fallback;
}

Eigen::Matrix4d YamlMap::get_matrix4(const std::string& key) const {
  const YAML::Node n = require(key);
  Eigen::Matrix4d m;
  if (n.IsSequence()) {  // Kalibr: 4 rows of 4
    if (n.size() != 4) fail(key, "expected a 4x4 matrix (4 rows), got " + std::to_string(n.size()) + " rows");
    for (int r = 0; r < 4; ++r) {
      const YAML::Node row = n[r];
      if (!row.IsSequence() || row.size() != 4) fail(key, "expected a 4x4 matrix, row " + std::to_string(r + 1) + " is not 4 numbers");
      for (int c = 0; c < 4; ++c) m(r, c) = to_double(row[c], key);
    }
    return m;
  }
  if (!n.IsMap()) fail(key, "expected a 4x4 matrix, got " + scalar_text(n));
  YamlMap sub = get_map(key);  // EuRoC / OpenCV: {cols, rows, data[, dt]}
  const int rows = sub.get_int("rows");
  const int cols = sub.get_int("cols");
  if (rows != 4 || cols != 4) sub.fail("rows", "expected rows: 4 and cols: 4");
  sub.accept("dt");
  const std::vector<double> d = sub.get_doubles("data", 16);
  sub.check_unknown();
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = d[i];
  return m;
}

YamlMap YamlMap::get_map(const std::string& key) const {
  const YAML::Node n = require(key);
  if (!n.IsMap()) fail(key, "expected a mapping, got " + scalar_text(n));
  return YamlMap(n, file_, full_key(key));
}

YamlMap YamlMap::get_map_or_empty(const std::string& key) const {
  if (!present(key)) return YamlMap(YAML::Node(YAML::NodeType::Map), file_, full_key(key));
  return get_map(key);
}

std::vector<YamlMap> YamlMap::get_maps(const std::string& key) const {
  std::vector<YamlMap> out;
  if (!present(key)) return out;
  const YAML::Node n = require(key);
  if (!n.IsSequence()) fail(key, "expected a list, got " + scalar_text(n));
  for (std::size_t i = 0; i < n.size(); ++i) {
    out.push_back(from_node(n[i], file_, full_key(key) + "[" + std::to_string(i) + "]"));
  }
  return out;
}

YAML::Node YamlMap::get_raw(const std::string& key) const {
  accept(key);
  return present(key) ? require(key) : YAML::Node(YAML::NodeType::Undefined);
}

std::optional<std::string> YamlMap::first_unknown() const {
  for (const auto& kv : node_) {
    const std::string k = kv.first.IsScalar() ? kv.first.Scalar() : "?";
    if (consumed_->count(k) == 0) return full_key(k);
  }
  return std::nullopt;
}

void YamlMap::check_unknown() const {
  for (const auto& kv : node_) {
    const std::string k = kv.first.IsScalar() ? kv.first.Scalar() : "?";
    if (consumed_->count(k) == 0) {
      throw ConfigError(file_ + ":" + std::to_string(kv.first.Mark().line + 1) + ": unknown key '" +
                        full_key(k) + "'");
    }
  }
}

}  // namespace vid::io
