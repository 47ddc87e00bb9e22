/// @file pose_track.cpp
/// @brief Recorded trajectory: TUM reading and the spline/slerp interpolation (pose_track.h).

#include "sim/pose_track.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/so3.h"
#include "io/csv_reader.h"

namespace vid::sim {

namespace {

/// @brief Stamp [s] of TUM column 1 as ns. Plain decimal text ("1525745865.001655340") is
/// converted exactly (rounded at the 10th decimal); other number forms ("1.5e9") go through
/// the double. Throws (via the reader) for text, NaN/Inf, negative or out-of-range stamps.
TimeNs stamp_ns(const io::CsvReader& in) {
  const double t_s = in.get_double(0, "t");  // validates the number, names file:line:column
  if (t_s < 0.0) in.fail("column 1 't': negative timestamp " + std::string(in.field(0)));
  if (t_s > 9.2e9) in.fail("column 1 't': timestamp " + std::string(in.field(0)) + " s out of range (> 9.2e9 s)");
  std::string_view f = in.field(0);
  if (!f.empty() && f.front() == '+') f.remove_prefix(1);
  const std::size_t dot = f.find('.');
  const std::string_view whole = f.substr(0, dot);
  const std::string_view frac = dot == std::string_view::npos ? std::string_view{} : f.substr(dot + 1);
  const auto digits = [](std::string_view s) { return std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }); };
  if (whole.empty() || !digits(whole) || !digits(frac)) return static_cast<TimeNs>(std::llround(t_s * 1e9));
  std::int64_t sec = 0;
  std::from_chars(whole.data(), whole.data() + whole.size(), sec);
  std::int64_t ns = 0;
  for (std::size_t i = 0; i < 9; ++i) ns = ns * 10 + (i < frac.size() ? frac[i] - '0' : 0);
  if (frac.size() > 9 && frac[9] >= '5') ++ns;  // round half up at the ns
  return sec * 1'000'000'000LL + ns;
}

}  // namespace

PoseTrack::PoseTrack(std::vector<TimeNs> t_ns, std::vector<Eigen::Vector3d> p_WI, std::vector<Eigen::Quaterniond> q_WI)
    : t_ns_(std::move(t_ns)), p_(std::move(p_WI)), q_(std::move(q_WI)) {
  const std::size_t n = t_ns_.size();
  if (n < 2) throw std::invalid_argument("pose track: need at least 2 poses, got " + std::to_string(n));
  if (p_.size() != n || q_.size() != n) throw std::invalid_argument("pose track: times, positions and orientations differ in count");
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && !(t_ns_[i] > t_ns_[i - 1]))
      throw std::invalid_argument("pose track: pose " + std::to_string(i) + ": time not after the previous pose's");
    if (!p_[i].allFinite() || !q_[i].coeffs().allFinite() || std::abs(q_[i].norm() - 1.0) > kUnitTolerance)
      throw std::invalid_argument("pose track: pose " + std::to_string(i) + ": not a finite position and unit quaternion");
    q_[i].normalize();
  }
  t_s_.resize(n);
  for (std::size_t i = 0; i < n; ++i) t_s_[i] = seconds(t_ns_[i]);

  // Natural cubic spline: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (slope_i - slope_{i-1}),
  // M_0 = M_{n-1} = 0; tridiagonal, solved by the Thomas algorithm (diagonally dominant).
  m_.assign(n, Eigen::Vector3d::Zero());
  if (n > 2) {
    std::vector<double> diag(n), upper(n);
    std::vector<Eigen::Vector3d> rhs(n, Eigen::Vector3d::Zero());
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t_s_[i] - t_s_[i - 1], h1 = t_s_[i + 1] - t_s_[i];
      diag[i] = 2.0 * (h0 + h1);
      upper[i] = h1;
      rhs[i] = 6.0 * ((p_[i + 1] - p_[i]) / h1 - (p_[i] - p_[i - 1]) / h0);
      if (i > 1) {  // eliminate the sub-diagonal h0 against row i - 1
        const double f = h0 / diag[i - 1];
        diag[i] -= f * upper[i - 1];
        rhs[i] -= f * rhs[i - 1];
      }
    }
    for (std::size_t i = n - 2; i >= 1; --i) {
      m_[i] = (rhs[i] - upper[i] * m_[i + 1]) / diag[i];
      if (i == 1) break;
    }
  }
  w_I_.resize(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) w_I_[i] = so3::boxminus(q_[i + 1], q_[i]) / (t_s_[i + 1] - t_s_[i]);
}

PoseTrack PoseTrack::read_tum(const std::filesystem::path& file) {
  io::CsvReader in(file, ' ');
  static constexpr std::array<const char*, 8> kColumns = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
  std::vector<TimeNs> t;
  std::vector<Eigen::Vector3d> p;
  std::vector<Eigen::Quaterniond> q;
  while (in.next_row()) {
    in.expect_columns(kColumns.size());
    const TimeNs t_ns = stamp_ns(in);
    if (!t.empty() && t_ns <= t.back())
      in.fail("column 1 't': timestamp " + std::string(in.field(0)) + " not after the previous row's");
    std::array<double, 7> v{};
    for (std::size_t i = 1; i < kColumns.size(); ++i) v[i - 1] = in.get_double(i, kColumns[i]);
    const Eigen::Quaterniond q_WI(v[6], v[3], v[4], v[5]);  // TUM order qx qy qz qw
    if (std::abs(q_WI.norm() - 1.0) > kUnitTolerance)
      in.fail("columns 5-8 'qx qy qz qw': not a unit quaternion (norm " + std::to_string(q_WI.norm()) + ")");
    t.push_back(t_ns);
    p.emplace_back(v[0], v[1], v[2]);
    q.push_back(q_WI);
  }
  if (t.size() < 2) throw io::DatasetError(file.string() + ": need at least 2 poses, found " + std::to_string(t.size()));
  return PoseTrack(std::move(t), std::move(p), std::move(q));
}

std::size_t PoseTrack::interval(TimeNs t_ns) const {
  const auto it = std::upper_bound(t_ns_.begin(), t_ns_.end(), t_ns);
  const std::size_t after = static_cast<std::size_t>(it - t_ns_.begin());  // first sample later than t
  return std::clamp<std::size_t>(after, 1, t_ns_.size() - 1) - 1;
}

Eigen::Isometry3d PoseTrack::pose(TimeNs t_ns) const {
  t_ns = std::clamp(t_ns, start_ns(), end_ns());
  const std::size_t i = interval(t_ns);
  const double h = t_s_[i + 1] - t_s_[i];
  const double b = (seconds(t_ns) - t_s_[i]) / h, a = 1.0 - b;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = a * p_[i] + b * p_[i + 1] + ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * (h * h / 6.0);
  T.linear() = (q_[i] * so3::quat_exp(b * h * w_I_[i])).normalized().toRotationMatrix();
  return T;
}

BodyMotion PoseTrack::motion(TimeNs t_ns) const {
  t_ns = std::clamp(t_ns, start_ns(), end_ns());
  const std::size_t i = interval(t_ns);
  const double h = t_s_[i + 1] - t_s_[i];
  const double b = (seconds(t_ns) - t_s_[i]) / h, a = 1.0 - b;
  BodyMotion m;
  m.v_WI = (p_[i + 1] - p_[i]) / h - (3.0 * a * a - 1.0) * h / 6.0 * m_[i] + (3.0 * b * b - 1.0) * h / 6.0 * m_[i + 1];
  m.a_WI = a * m_[i] + b * m_[i + 1];
  m.w_I = w_I_[i];
  return m;
}

}  // namespace vid::sim
