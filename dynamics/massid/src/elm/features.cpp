/// @file features.cpp
/// @brief Causal feature extraction and normalization for ELM/RELM/OSELM (seed section 4.2.5).
#include "massid/elm/features.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/so3.h"

namespace vid::massid::elm {

FeatureExtractor::FeatureExtractor(FeatureConfig config, bool partial_windows)
    : config_(std::move(config)), partial_(partial_windows) {
  if (config_.windows.empty()) throw std::invalid_argument("FeatureConfig: no windows");
  for (size_t i = 0; i < config_.windows.size(); ++i) {
    if (!(config_.windows[i] > 0.0) || (i > 0 && !(config_.windows[i] > config_.windows[i - 1]))) {
      throw std::invalid_argument("FeatureConfig: windows must be positive and ascending");
    }
  }
  if (config_.train_stride < 1) throw std::invalid_argument("FeatureConfig: train_stride < 1");
}

void FeatureExtractor::reset(double gravity) {
  gravity_ = gravity;
  history_.clear();
}

bool FeatureExtractor::push(const MassIdSample& s, Eigen::VectorXd* x) {
  const Eigen::Quaterniond q = s.q_WI.normalized();
  const Eigen::Vector3d z_W = q * Eigen::Vector3d::UnitZ();
  Entry e{s.t, s.v_WI, Eigen::Vector3d::Zero()};
  if (!history_.empty()) {
    const Entry& prev = history_.back();
    if (!(s.t > prev.t)) {
      throw std::invalid_argument("FeatureExtractor: time does not increase at t = " +
                                  std::to_string(s.t));
    }
    // Commands are held over a sample interval (zero-order hold, as the vehicle applies
    // them): thrust T_{k-1} along z_I at the interval's midpoint attitude
    // R_{k-1} Exp(w_{k-1} dt / 2).
    const double dt = s.t - prev.t;
    const Eigen::Quaterniond dq = so3::quat_exp(0.5 * dt * last_.w_I);
    const Eigen::Vector3d z_mid = (last_.q_WI * dq) * Eigen::Vector3d::UnitZ();
    e.thrust_integral_W = prev.thrust_integral_W + dt * last_.thrust_cmd * z_mid;
  }
  history_.push_back(e);
  last_ = s;
  last_.q_WI = q;

  const double longest = config_.windows.back();
  // Keep the newest sample at or before t - longest, drop anything older.
  while (history_.size() >= 2 && history_[1].t <= s.t - longest) history_.pop_front();
  if (history_.front().t > s.t - longest &&
      (!partial_ || history_.front().t > s.t - config_.windows.front())) {
    return false;
  }

  x->resize(config_.dimension());
  int c = 0;
  const Eigen::Vector3d g_e = gravity_ * Eigen::Vector3d::UnitZ();
  for (double window : config_.windows) {
    // Newest entry j with t_j <= t_k - window (history is sorted by t).
    auto it = std::upper_bound(history_.begin(), history_.end(), s.t - window,
                               [](double t, const Entry& en) { return t < en.t; });
    // Partial mode before the window is covered: the oldest sample (shorter effective window).
    const Entry& j = it == history_.begin() ? history_.front() : *(it - 1);
    const double dt = s.t - j.t;
    const Eigen::Vector3d a_W = (e.v_W - j.v_W) / dt + g_e;
    const Eigen::Vector3d f_W = (e.thrust_integral_W - j.thrust_integral_W) / dt;
    x->segment<3>(c) = a_W;
    x->segment<3>(c + 3) = f_W;
    c += 6;
    if (config_.physics_ratio) {
      (*x)(c++) = f_W.dot(a_W) / std::max(a_W.squaredNorm(), 1e-6);
    }
  }
  (*x)(c++) = s.thrust_cmd;
  x->segment<3>(c) = s.w_I;
  x->segment<3>(c + 3) = z_W;
  return true;
}

RunFeatures extract_run_features(const MassIdRun& run, const FeatureConfig& config, int stride,
                                 bool partial_windows) {
  FeatureExtractor extractor(config, partial_windows);
  extractor.reset(run.info.gravity);
  RunFeatures out;
  std::vector<Eigen::VectorXd> rows;
  std::vector<double> targets;
  Eigen::VectorXd x;
  int valid = 0;
  for (size_t k = 0; k < run.samples.size(); ++k) {
    if (!extractor.push(run.samples[k], &x)) continue;
    if (valid++ % stride != 0) continue;
    rows.push_back(x);
    targets.push_back(run.samples[k].mass_true);
    out.sample_index.push_back(static_cast<int>(k));
  }
  out.X.resize(static_cast<Eigen::Index>(rows.size()), config.dimension());
  out.y.resize(static_cast<Eigen::Index>(rows.size()));
  for (size_t r = 0; r < rows.size(); ++r) {
    out.X.row(static_cast<Eigen::Index>(r)) = rows[r].transpose();
    out.y(static_cast<Eigen::Index>(r)) = targets[r];
  }
  return out;
}

RunFeatures extract_training_set(const std::vector<const MassIdRun*>& runs,
                                 const FeatureConfig& config) {
  std::vector<RunFeatures> parts;
  Eigen::Index total = 0;
  for (const MassIdRun* run : runs) {
    parts.push_back(extract_run_features(*run, config, config.train_stride));
    total += parts.back().X.rows();
  }
  if (total == 0) throw std::invalid_argument("extract_training_set: no feature rows (runs too short?)");
  RunFeatures out;
  out.X.resize(total, config.dimension());
  out.y.resize(total);
  Eigen::Index r = 0;
  for (const RunFeatures& p : parts) {
    out.X.middleRows(r, p.X.rows()) = p.X;
    out.y.segment(r, p.y.size()) = p.y;
    out.sample_index.insert(out.sample_index.end(), p.sample_index.begin(), p.sample_index.end());
    r += p.X.rows();
  }
  return out;
}

Normalizer Normalizer::fit(const Eigen::MatrixXd& X, const Eigen::VectorXd& y) {
  if (X.rows() == 0 || X.rows() != y.size()) {
    throw std::invalid_argument("Normalizer::fit: empty or mismatched training data");
  }
  Normalizer n;
  const double N = static_cast<double>(X.rows());
  n.mean = X.colwise().mean().transpose();
  n.stddev = ((X.rowwise() - n.mean.transpose()).array().square().colwise().sum() / N)
                 .sqrt()
                 .transpose();
  for (Eigen::Index i = 0; i < n.stddev.size(); ++i) {
    if (!(n.stddev(i) > 1e-12)) n.stddev(i) = 1.0;
  }
  n.y_mean = y.mean();
  n.y_std = std::sqrt((y.array() - n.y_mean).square().sum() / N);
  if (!(n.y_std > 1e-12)) n.y_std = 1.0;
  return n;
}

Eigen::MatrixXd Normalizer::apply(const Eigen::MatrixXd& X) const {
  return ((X.rowwise() - mean.transpose()).array().rowwise() / stddev.transpose().array())
      .matrix();
}

Eigen::VectorXd Normalizer::apply_row(const Eigen::VectorXd& x) const {
  return ((x - mean).array() / stddev.array()).matrix();
}

Eigen::VectorXd Normalizer::apply_target(const Eigen::VectorXd& y) const {
  return ((y.array() - y_mean) / y_std).matrix();
}

}  // namespace vid::massid::elm
