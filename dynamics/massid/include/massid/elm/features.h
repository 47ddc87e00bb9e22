#pragma once
/// @file features.h
/// @brief Input vector and target of the data-driven mass estimators (seed section 4.2.5),
/// extracted causally from a run's samples, and their normalization.
///
/// Input vector x_k at sample k, using only samples with t <= t_k (so the same extractor runs
/// online). For each window length D in FeatureConfig::windows (default 0.05, 0.1, 0.2, 0.4 s),
/// with j the newest sample such that t_j <= t_k - D:
///   * a_W = (v_k - v_j) / (t_k - t_j) + g e_z          specific acceleration from the measured
///     velocity by a finite difference over the window, world frame [m/s^2] (3)
///   * f_W = (1 / (t_k - t_j)) * int_{t_j}^{t_k} T_cmd z_I dt   mean commanded thrust vector in
///     W [N] (3): commands held over each sample interval (zero-order hold, as the vehicle
///     applies them), z_I at the interval's midpoint attitude R_i Exp(w_i dt / 2) propagated
///     from the measured attitude with the commanded rate
///   * m_D = f_W . a_W / |a_W|^2                     the window's least-squares mass from
///     m a_W = f_W (integrated Newton's law) [kg] (1); only if FeatureConfig::physics_ratio
/// and at sample k itself:
///   * T_cmd [N] (1), body rates w_I [rad/s] (3), attitude as z_I in W (3).
/// Default: 4 windows x 7 + 7 = 35 inputs. Target: mass_true [kg].
/// The window features are exactly the quantities of the integrated translational dynamics
/// m (v_k - v_j) = int (T z_I - m g e_z) dt, so the network learns the map from thrust and
/// acceleration to mass. Short windows follow mass steps quickly but carry the velocity noise
/// (sqrt(2) sigma_v / D), long ones are smooth but lag a step by D; the network weighs them.
/// The windows were chosen on held-out runs of the study (dynamics/massid/README.md,
/// "Data-driven methods").

#include <Eigen/Core>
#include <deque>
#include <vector>

#include "massid/run_data.h"

namespace vid::massid::elm {

/// @brief Feature definition.
struct FeatureConfig {
  std::vector<double> windows{0.05, 0.1, 0.2, 0.4};  ///< finite-difference windows [s], ascending
  bool physics_ratio = true;                    ///< add m_D per window
  int train_stride = 2;  ///< training uses every stride-th sample of a run (neighbours are
                         ///< near-duplicates at 100 Hz); prediction uses every sample
  /// @brief Number of inputs d.
  int dimension() const { return static_cast<int>(windows.size()) * (physics_ratio ? 7 : 6) + 7; }
};

/// @brief Causal, streaming feature extractor (one per run).
class FeatureExtractor {
 public:
  /// @param partial_windows  false (training): features only once the longest window is
  ///        covered; true (prediction): already once the shortest one is, windows not yet
  ///        covered then span from the run's first sample (shorter, noisier averages)
  /// @throws std::invalid_argument when windows are empty, non-positive or not ascending
  explicit FeatureExtractor(FeatureConfig config = {}, bool partial_windows = false);
  /// @brief Forget all samples; gravity magnitude [m/s^2] from the run's info.
  void reset(double gravity);
  /// @brief Add the next sample (strictly increasing t). Returns true and writes x (d) once
  /// the longest (partial mode: shortest) window is covered; false before that.
  /// @throws std::invalid_argument when t does not increase
  bool push(const MassIdSample& sample, Eigen::VectorXd* x);
  const FeatureConfig& config() const { return config_; }

 private:
  struct Entry {
    double t;
    Eigen::Vector3d v_W;
    Eigen::Vector3d thrust_integral_W;  ///< int_{t_0}^{t} T_cmd z_I dt [N s]
  };
  FeatureConfig config_;
  bool partial_ = false;
  double gravity_ = kDefaultGravity;
  std::deque<Entry> history_;
  MassIdSample last_;  ///< previous sample (its commands act over the last interval)
};

/// @brief Features and targets of a run, every stride-th sample whose features exist.
struct RunFeatures {
  Eigen::MatrixXd X;               ///< N x d
  Eigen::VectorXd y;               ///< N, mass_true [kg]
  std::vector<int> sample_index;   ///< row -> index into run.samples
};

/// @brief Run the extractor over a whole run (stride 1 = every sample).
RunFeatures extract_run_features(const MassIdRun& run, const FeatureConfig& config, int stride,
                                 bool partial_windows = false);

/// @brief Stack the features of several runs (training stride of the config).
/// @throws std::invalid_argument when no run yields a feature row
RunFeatures extract_training_set(const std::vector<const MassIdRun*>& runs,
                                 const FeatureConfig& config);

/// @brief Per-column z-score normalization fitted on training data: x' = (x - mean) / std
/// (std of a constant column is taken as 1); target y' = (y - y_mean) / y_std.
struct Normalizer {
  Eigen::VectorXd mean, stddev;
  double y_mean = 0.0, y_std = 1.0;
  /// @throws std::invalid_argument on an empty X
  static Normalizer fit(const Eigen::MatrixXd& X, const Eigen::VectorXd& y);
  Eigen::MatrixXd apply(const Eigen::MatrixXd& X) const;
  Eigen::VectorXd apply_row(const Eigen::VectorXd& x) const;
  Eigen::VectorXd apply_target(const Eigen::VectorXd& y) const;
  double invert_target(double y_normalized) const { return y_mean + y_std * y_normalized; }
};

}  // namespace vid::massid::elm
