/// @file run_csv.cpp
/// @brief The run CSV of run_data.h: writer (shortest round-trip decimal of every double, so a
/// read gives back the identical bits) and a strict reader that names file, line and field.
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

#include "massid/run_data.h"

namespace vid::massid {
namespace {

constexpr std::array<const char*, 16> kFields = {
    "t",  "qw", "qx", "qy", "qz", "px", "py", "pz",
    "vx", "vy", "vz", "thrust_cmd", "wx", "wy", "wz", "mass_true"};

std::string header_line() {
  std::string h;
  for (size_t i = 0; i < kFields.size(); ++i) {
    if (i > 0) h += ',';
    h += kFields[i];
  }
  return h;
}

/// Shortest decimal that parses back to the same double (std::to_chars round-trip guarantee).
void append_double(std::string* out, double x) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof(buf), x);
  out->append(buf, res.ptr);
}

std::array<double, 16> sample_values(const MassIdSample& s) {
  return {s.t,        s.q_WI.w(), s.q_WI.x(), s.q_WI.y(), s.q_WI.z(), s.p_WI.x(),
          s.p_WI.y(), s.p_WI.z(), s.v_WI.x(), s.v_WI.y(), s.v_WI.z(), s.thrust_cmd,
          s.w_I.x(),  s.w_I.y(),  s.w_I.z(),  s.mass_true};
}

[[noreturn]] void fail(const std::filesystem::path& file, size_t line, const std::string& msg) {
  throw std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + msg);
}

}  // namespace

void write_run_csv(const std::filesystem::path& file, const std::vector<MassIdSample>& samples) {
  std::string text = header_line();
  text += '\n';
  text.reserve(samples.size() * 200 + text.size());
  for (const MassIdSample& s : samples) {
    const auto values = sample_values(s);
    for (size_t i = 0; i < values.size(); ++i) {
      if (i > 0) text += ',';
      append_double(&text, values[i]);
    }
    text += '\n';
  }
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

std::vector<MassIdSample> read_run_csv(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open run CSV");
  std::string line;
  size_t line_no = 0;
  if (!std::getline(in, line)) fail(file, 1, "empty file, expected header '" + header_line() + "'");
  ++line_no;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (!line.empty() && line.front() == '#') line.erase(0, 1);
  if (line != header_line()) {
    fail(file, line_no, "bad header '" + line + "', expected '" + header_line() + "'");
  }
  std::vector<MassIdSample> samples;
  double t_prev = -INFINITY;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;  // tolerate a trailing blank line
    std::array<double, 16> v{};
    size_t field = 0;
    size_t pos = 0;
    while (true) {
      const size_t comma = line.find(',', pos);
      const std::string_view tok(line.data() + pos,
                                 (comma == std::string::npos ? line.size() : comma) - pos);
      if (field >= v.size()) {
        fail(file, line_no, "too many fields (expected " + std::to_string(v.size()) + ")");
      }
      const char* b = tok.data();
      const char* e = tok.data() + tok.size();
      while (b < e && *b == ' ') ++b;  // allow "a, b" spacing
      double x = 0.0;
      const auto res = std::from_chars(b, e, x);
      if (res.ec != std::errc() || res.ptr != e || !std::isfinite(x)) {
        fail(file, line_no,
             std::string("field '") + kFields[field] + "': not a finite number: '" +
                 std::string(tok) + "'");
      }
      v[field++] = x;
      if (comma == std::string::npos) break;
      pos = comma + 1;
    }
    if (field != v.size()) {
      fail(file, line_no,
           "expected " + std::to_string(v.size()) + " fields, got " + std::to_string(field) +
               " (missing field '" + kFields[field] + "')");
    }
    if (!(v[0] > t_prev)) fail(file, line_no, "field 't': time does not increase");
    t_prev = v[0];
    const double qn = std::sqrt(v[1] * v[1] + v[2] * v[2] + v[3] * v[3] + v[4] * v[4]);
    if (std::abs(qn - 1.0) > 1e-3) {  // allows hand-written CSVs with few digits
      fail(file, line_no, "fields 'qw,qx,qy,qz': quaternion norm " + std::to_string(qn) + " is not 1");
    }
    if (!(v[11] >= 0.0)) fail(file, line_no, "field 'thrust_cmd': negative thrust");
    if (!(v[15] > 0.0)) fail(file, line_no, "field 'mass_true': mass must be positive");
    MassIdSample s;
    s.t = v[0];
    s.q_WI = Eigen::Quaterniond(v[1], v[2], v[3], v[4]);
    s.p_WI = Eigen::Vector3d(v[5], v[6], v[7]);
    s.v_WI = Eigen::Vector3d(v[8], v[9], v[10]);
    s.thrust_cmd = v[11];
    s.w_I = Eigen::Vector3d(v[12], v[13], v[14]);
    s.mass_true = v[15];
    samples.push_back(s);
  }
  return samples;
}

}  // namespace vid::massid
