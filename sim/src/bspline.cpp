#include "bspline.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

namespace vid::sim::detail {

double UniformBSpline::cardinal(int d, double x) {
  if (x < 0.0 || x >= d + 1) return 0.0;
  if (d == 0) return 1.0;
  return (x * cardinal(d - 1, x) + (d + 1 - x) * cardinal(d - 1, x - 1.0)) / d;
}

UniformBSpline::UniformBSpline(Eigen::MatrixXd control, double t0, double dt) : t0_(t0), dt_(dt) {
  if (control.cols() < kDegree + 1) throw std::invalid_argument("B-spline: need >= 6 control points");
  if (!(dt > 0.0)) throw std::invalid_argument("B-spline: knot spacing must be > 0");
  diff_[0] = std::move(control);
  for (int r = 1; r < 5; ++r) {
    const Eigen::MatrixXd& p = diff_[r - 1];
    // Column i of the r-th difference pairs with basis index i + r of the original.
    diff_[r] = (p.rightCols(p.cols() - 1) - p.leftCols(p.cols() - 1)) / dt;
  }
}

double UniformBSpline::t_end() const { return t0_ + (diff_[0].cols() - kDegree) * dt_; }

std::array<Eigen::VectorXd, 5> UniformBSpline::eval(double t) const {
  t = std::clamp(t, t0_, t_end());
  // Spline coordinate: x = (t - t0)/dt + degree, basis i active when x - i in [0, degree+1).
  const double x = (t - t0_) / dt_ + kDegree;
  std::array<Eigen::VectorXd, 5> out;
  for (int r = 0; r < 5; ++r) {
    const int d = kDegree - r;
    const Eigen::MatrixXd& c = diff_[r];
    Eigen::VectorXd s = Eigen::VectorXd::Zero(c.rows());
    // Basis of the r-th derivative: N_{d}(x - i) with i the original index, column i - r.
    const int i_hi = static_cast<int>(std::floor(x));
    for (int i = i_hi - d; i <= i_hi; ++i) {
      const int col = i - r;
      if (col < 0 || col >= c.cols()) continue;
      const double b = cardinal(d, x - i);
      if (b != 0.0) s += b * c.col(col);
    }
    out[r] = s;
  }
  return out;
}

UniformBSpline UniformBSpline::fit(const std::vector<double>& times, const Eigen::MatrixXd& values,
                                   double dt, double regularization) {
  if (times.size() < 2) throw std::invalid_argument("B-spline fit: need >= 2 samples");
  const double t0 = times.front();
  const double span = times.back() - t0;
  const int M = static_cast<int>(std::ceil(span / dt)) + kDegree + 1;
  const int D = static_cast<int>(values.rows());
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(M, M);
  Eigen::MatrixXd AtY = Eigen::MatrixXd::Zero(M, D);
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double x = (times[k] - t0) / dt + kDegree;
    const int i_hi = static_cast<int>(std::floor(x));
    for (int i = i_hi - kDegree; i <= i_hi; ++i) {
      if (i < 0 || i >= M) continue;
      const double bi = cardinal(kDegree, x - i);
      for (int j = i_hi - kDegree; j <= i_hi; ++j) {
        if (j < 0 || j >= M) continue;
        AtA(i, j) += bi * cardinal(kDegree, x - j);
      }
      AtY.row(i) += bi * values.col(static_cast<Eigen::Index>(k)).transpose();
    }
  }
  // Second-difference penalty keeps control points without data (gaps, ends) well defined.
  const double w = regularization * static_cast<double>(times.size()) / M;
  for (int i = 1; i + 1 < M; ++i) {
    const int idx[3] = {i - 1, i, i + 1};
    const double c[3] = {1.0, -2.0, 1.0};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) AtA(idx[a], idx[b]) += w * c[a] * c[b];
  }
  const Eigen::MatrixXd ctrl = AtA.ldlt().solve(AtY).transpose();
  return UniformBSpline(ctrl, t0, dt);
}

}  // namespace vid::sim::detail
