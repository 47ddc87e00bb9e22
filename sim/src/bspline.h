#pragma once
/// @file bspline.h
/// @brief Uniform B-spline of degree 5 (C4) in R^D, evaluated with derivatives up to order 4
/// by differencing control points. Private to sim (trajectories).

#include <Eigen/Core>
#include <array>
#include <vector>

namespace vid::sim::detail {

/// @brief s(t) = sum_i c_i N5((t - t0)/dt - i + 5), valid for t in [t0, t0 + (M - 5) dt].
class UniformBSpline {
 public:
  static constexpr int kDegree = 5;
  UniformBSpline() = default;
  /// @param control  M >= 6 control points (columns)
  UniformBSpline(Eigen::MatrixXd control, double t0, double dt);
  /// @brief Value and derivatives 0..4 at t (t clamped to the valid range).
  std::array<Eigen::VectorXd, 5> eval(double t) const;
  double t_begin() const { return t0_; }
  double t_end() const;
  double dt() const { return dt_; }
  /// @brief Cardinal B-spline basis of degree d at x (support [0, d+1)).
  static double cardinal(int d, double x);
  /// @brief Least-squares fit of control points to samples (t_k, y_k) with knot spacing dt and
  /// a small smoothness regulariser; the spline starts at t0 = times.front().
  static UniformBSpline fit(const std::vector<double>& times, const Eigen::MatrixXd& values,
                            double dt, double regularization = 1e-6);
  const Eigen::MatrixXd& control() const { return diff_[0]; }

 private:
  std::array<Eigen::MatrixXd, 5> diff_;  ///< control points differenced r times, / dt^r
  double t0_ = 0.0;
  double dt_ = 1.0;
};

}  // namespace vid::sim::detail
