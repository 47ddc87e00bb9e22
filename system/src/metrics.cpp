#include "vid_system/metrics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include <fmt/format.h>

namespace vid::system {

namespace {
/// A stamp as evo holds it: the double nearest the decimal text of a TUM file (strtod rounds
/// correctly, as Python's float() does), or double(ns) / 1e9 for an ASL CSV.
std::vector<double> evo_seconds(const std::vector<TimeNs>& t, StampText text) {
  std::vector<double> s(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (text == StampText::kNanoseconds) {
      s[i] = static_cast<double>(t[i]) / 1e9;
    } else {
      const TimeNs a = t[i] < 0 ? -t[i] : t[i];
      const std::string dec = fmt::format("{}{}.{:09d}", t[i] < 0 ? "-" : "", a / 1'000'000'000, a % 1'000'000'000);
      s[i] = std::strtod(dec.c_str(), nullptr);
    }
  }
  return s;
}

/// For each of a (sorted) the nearest of sorted b within tol; ties go to the earlier sample.
std::vector<std::pair<std::size_t, std::size_t>> nearest(const std::vector<double>& a, const std::vector<double>& b,
                                                         double tol) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  if (a.empty() || b.empty()) return out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double s = a[i];
    if (s < b.front() - tol || s > b.back() + tol) continue;
    std::size_t j = static_cast<std::size_t>(std::upper_bound(b.begin(), b.end(), s) - b.begin());
    j = std::min(j, b.size() - 1);
    const double d_up = b[j] - s;
    const double d_lo = j > 0 ? s - b[j - 1] : std::numeric_limits<double>::infinity();
    if (d_up <= tol && d_up < d_lo) {
      out.emplace_back(i, j);
    } else if (d_lo <= tol && d_lo <= d_up) {
      out.emplace_back(i, j - 1);
    }
  }
  return out;
}
}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> associate_nearest(const std::vector<TimeNs>& t_est,
                                                                   const std::vector<TimeNs>& t_gt,
                                                                   TimeNs max_diff_ns, StampText est_text,
                                                                   StampText gt_text) {
  const std::vector<double> s_est = evo_seconds(t_est, est_text), s_gt = evo_seconds(t_gt, gt_text);
  const double tol = static_cast<double>(max_diff_ns) / 1e9;
  if (t_est.size() <= t_gt.size()) return nearest(s_est, s_gt, tol);
  auto swapped = nearest(s_gt, s_est, tol);
  for (auto& p : swapped) std::swap(p.first, p.second);
  return swapped;
}

std::optional<AteResult> ate_posyaw(const Vec3Series& est, const Vec3Series& gt) {
  // As vid-eval pairs trajectory_tum.txt (seconds) with the ASL ground truth (ns).
  const auto pairs = associate_nearest(est.t_ns, gt.t_ns, 10'000'000, StampText::kSeconds, StampText::kNanoseconds);
  if (pairs.empty()) return std::nullopt;
  const double n = static_cast<double>(pairs.size());
  Eigen::Vector3d mu_e = Eigen::Vector3d::Zero();
  Eigen::Vector3d mu_g = Eigen::Vector3d::Zero();
  for (const auto& [ie, ig] : pairs) {
    mu_e += est.v[ie];
    mu_g += gt.v[ig];
  }
  mu_e /= n;
  mu_g /= n;
  // Closed form: yaw = atan2(sum(a_x b_y - a_y b_x), sum(a_x b_x + a_y b_y)) on centred points.
  double num = 0.0;
  double den = 0.0;
  for (const auto& [ie, ig] : pairs) {
    const Eigen::Vector3d a = est.v[ie] - mu_e;
    const Eigen::Vector3d b = gt.v[ig] - mu_g;
    num += a.x() * b.y() - a.y() * b.x();
    den += a.x() * b.x() + a.y() * b.y();
  }
  AteResult r;
  r.yaw_rad = (num != 0.0 || den != 0.0) ? std::atan2(num, den) : 0.0;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(r.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  r.translation = mu_g - R * mu_e;
  double sq = 0.0;
  for (const auto& [ie, ig] : pairs) sq += (R * est.v[ie] + r.translation - gt.v[ig]).squaredNorm();
  r.rmse_m = std::sqrt(sq / n);
  r.pairs = pairs.size();
  return r;
}

Vec3Series slice(const Vec3Series& s, TimeNs t0, TimeNs t1) {
  Vec3Series out;
  for (std::size_t i = 0; i < s.t_ns.size(); ++i) {
    if (s.t_ns[i] < t0 || s.t_ns[i] >= t1) continue;
    out.t_ns.push_back(s.t_ns[i]);
    out.v.push_back(s.v[i]);
  }
  return out;
}

std::optional<SegmentedAte> ate_posyaw_segments(const Vec3Series& est, const Vec3Series& gt,
                                                const std::vector<TimeNs>& starts) {
  std::vector<TimeNs> cuts = starts.size() < 2 ? std::vector<TimeNs>{INT64_MIN} : starts;
  cuts.front() = INT64_MIN;  // the first piece also holds anything before the first start
  SegmentedAte r;
  double sq = 0.0;
  for (std::size_t k = 0; k < cuts.size(); ++k) {
    const TimeNs t1 = k + 1 < cuts.size() ? cuts[k + 1] : INT64_MAX;
    const std::optional<AteResult> a = ate_posyaw(slice(est, cuts[k], t1), gt);
    if (!a) continue;
    if (r.segments.empty()) r.pooled.yaw_rad = a->yaw_rad;
    r.t_start_ns.push_back(k == 0 && !starts.empty() ? starts.front() : cuts[k]);
    r.segments.push_back(*a);
    sq += a->rmse_m * a->rmse_m * static_cast<double>(a->pairs);
    r.pooled.pairs += a->pairs;
  }
  if (r.pooled.pairs == 0) return std::nullopt;
  r.pooled.rmse_m = std::sqrt(sq / static_cast<double>(r.pooled.pairs));
  return r;
}

std::optional<double> force_rmse(const Vec3Series& est, const Vec3Series& gt, std::size_t* pairs_out) {
  const auto pairs = associate_nearest(est.t_ns, gt.t_ns);
  if (pairs_out != nullptr) *pairs_out = pairs.size();
  if (pairs.empty()) return std::nullopt;
  double sq = 0.0;
  for (const auto& [ie, ig] : pairs) sq += (est.v[ie] - gt.v[ig]).squaredNorm();
  return std::sqrt(sq / static_cast<double>(pairs.size()));
}

Vec3Series rotate_about_z(const Vec3Series& s, double yaw_rad) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Vec3Series out = s;
  for (auto& v : out.v) v = R * v;
  return out;
}

Vec3Series world_to_body(const Vec3Series& f_W, const std::vector<TimeNs>& t_R,
                         const std::vector<Eigen::Matrix3d>& R_WI) {
  Vec3Series out;
  for (const auto& [i_f, i_R] : associate_nearest(f_W.t_ns, t_R)) {
    out.t_ns.push_back(f_W.t_ns[i_f]);
    out.v.push_back(R_WI[i_R].transpose() * f_W.v[i_f]);
  }
  return out;
}

double mass_at(const std::vector<TimeNs>& t_ns, const std::vector<double>& mass_kg, TimeNs t) {
  if (t <= t_ns.front()) return mass_kg.front();
  if (t >= t_ns.back()) return mass_kg.back();
  const std::size_t j = static_cast<std::size_t>(std::upper_bound(t_ns.begin(), t_ns.end(), t) - t_ns.begin());
  const double w = static_cast<double>(t - t_ns[j - 1]) / static_cast<double>(t_ns[j] - t_ns[j - 1]);
  return mass_kg[j - 1] + w * (mass_kg[j] - mass_kg[j - 1]);
}

}  // namespace vid::system
