/// @file run_csv.cpp
/// @brief The run CSV of run_data.h: writer (shortest round-trip decimal of every double, so a
/// read gives back the identical bits) and a strict reader that names file, line and field.
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include "io/csv_reader.h"
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
  io::CsvReader in(file);
  in.read_header(std::vector<std::string>(kFields.begin(), kFields.end()));
  std::vector<MassIdSample> samples;
  double t_prev = -INFINITY;
  while (in.next_row()) {
    if (in.size() > kFields.size()) in.fail("too many fields (expected " + std::to_string(kFields.size()) + ")");
    if (in.size() < kFields.size()) {
      in.fail("expected " + std::to_string(kFields.size()) + " fields, got " + std::to_string(in.size()) +
              " (missing field '" + kFields[in.size()] + "')");
    }
    std::array<double, kFields.size()> v{};
    for (size_t i = 0; i < kFields.size(); ++i) v[i] = in.get_double(i, kFields[i]);
    if (!(v[0] > t_prev)) in.fail("field 't': time does not increase");
    t_prev = v[0];
    const double qn = std::sqrt(v[1] * v[1] + v[2] * v[2] + v[3] * v[3] + v[4] * v[4]);
    if (std::abs(qn - 1.0) > 1e-3) {  // allows hand-written CSVs with few digits
      in.fail("fields 'qw,qx,qy,qz': quaternion norm " + std::to_string(qn) + " is not 1");
    }
    if (!(v[11] >= 0.0)) in.fail("field 'thrust_cmd': negative thrust");
    if (!(v[15] > 0.0)) in.fail("field 'mass_true': mass must be positive");
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
