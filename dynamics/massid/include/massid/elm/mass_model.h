#pragma once
/// @file mass_model.h
/// @brief A trained ELM / RELM / OSELM mass model (seed section 4.2.5: Algorithm 1, eq. 29,
/// Algorithm 2) and the per-sample MassEstimator built on it.
///
/// Training: features of the training runs (features.h, every train_stride-th sample) are
/// z-score normalized, passed through the seeded random hidden layer, and the output weights
/// solved by QR (elm), Cholesky of the ridge normal equations (relm, eq. 29) or the Woodbury
/// recursion over chunks in time order (oselm, eqs. 30-38).
/// Prediction: the estimator runs the same causal extractor online; from the first shortest
/// window on it predicts (windows not yet covered span from the run's start), before that it
/// returns the run's initial mass guess.
/// OSELM at test time: the true mass is never available online, so the network is frozen
/// after training (it keeps no labels to learn from); its online character is the chunked
/// training, whose per-sample update cost is reported.

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "massid/elm/elm.h"
#include "massid/elm/features.h"
#include "massid/estimator.h"

namespace vid::massid::elm {

/// @brief Which solver.
enum class Method { kElm, kRelm, kOselm };
/// @brief "elm" | "relm" | "oselm". @throws std::invalid_argument otherwise
Method parse_method(const std::string& name);
std::string method_name(Method m);

/// @brief Model settings beyond DataDrivenOptions.
struct ModelConfig {
  FeatureConfig features;
  /// Half-width of the uniform input weights/biases; 0 = 1 / sqrt(d) scaled by 2, which keeps
  /// the sigmoid pre-activations of z-scored inputs mostly in the non-saturated range.
  double weight_scale = 0.0;
  /// OSELM chunk sizes, used cyclically; empty = DataDrivenOptions::oselm_chunk (fixed).
  std::vector<int> oselm_chunks;
};

/// @brief Training diagnostics.
struct TrainStats {
  long rows = 0;                 ///< training samples N
  double feature_seconds = 0.0;  ///< feature extraction + normalization
  double solve_seconds = 0.0;    ///< hidden layer + output weights
  double weight_norm = 0.0;      ///< Frobenius norm of beta (seed table 1)
  double train_rmse_percent = 0.0;
  long oselm_updates = 0;        ///< sequential-phase chunks
  double oselm_update_seconds = 0.0;  ///< total time spent in sequential-phase updates
};

/// @brief Trained network: normalizer + hidden layer + output weights.
class MassModel {
 public:
  /// @brief Train on the given runs.
  /// @throws std::invalid_argument on an empty training set or bad options
  static std::shared_ptr<const MassModel> train(Method method,
                                                const std::vector<const MassIdRun*>& runs,
                                                const DataDrivenOptions& options,
                                                const ModelConfig& config = {},
                                                TrainStats* stats = nullptr);
  /// @brief Mass [kg] from one raw (unnormalized) feature vector.
  double predict(const Eigen::VectorXd& x_raw) const;
  /// @brief Per-sample mass estimate of a whole run, identical to feeding the estimator.
  std::vector<double> predict_run(const MassIdRun& run) const;

  Method method() const { return method_; }
  const ModelConfig& config() const { return config_; }
  const Eigen::MatrixXd& beta() const { return beta_; }
  const HiddenLayer& hidden_layer() const { return layer_; }

 private:
  Method method_ = Method::kRelm;
  ModelConfig config_;
  Normalizer normalizer_;
  HiddenLayer layer_;
  Eigen::MatrixXd beta_;
};

/// @brief MassEstimator over a trained model (causal features, one prediction per sample).
class ElmMassEstimator : public MassEstimator {
 public:
  explicit ElmMassEstimator(std::shared_ptr<const MassModel> model);
  std::string name() const override { return method_name(model_->method()); }
  void reset(const RunInfo& info, const MassIdSample& first) override;
  double update(const MassIdSample& sample) override;
  const MassModel& model() const { return *model_; }

 private:
  std::shared_ptr<const MassModel> model_;
  FeatureExtractor extractor_;
  double initial_guess_ = 0.0;
  double last_t_ = 0.0;
  bool primed_ = false;
  Eigen::VectorXd x_;
};

}  // namespace vid::massid::elm
