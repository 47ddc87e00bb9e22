/// @file mass_model.cpp
/// @brief Training and prediction of the ELM / RELM / OSELM mass models (seed section
/// 4.2.5: Algorithm 1, eq. 29, Algorithm 2 eqs. 30-38).
#include "massid/elm/mass_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "massid/elm/oselm.h"

namespace vid::massid::elm {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// OSELM over the rows of H in order: initial batch, then chunks (cyclic sizes).
Eigen::MatrixXd train_oselm(const Eigen::MatrixXd& H, const Eigen::VectorXd& T,
                            const DataDrivenOptions& options, const ModelConfig& config,
                            TrainStats* stats) {
  const Eigen::Index N = H.rows();
  const Eigen::Index L = H.cols();
  // Default initial batch: 2 L rows (well determined without leaning on the prior).
  Eigen::Index n0 = options.oselm_initial_samples > 0 ? options.oselm_initial_samples : 2 * L;
  n0 = std::min(n0, N);
  std::vector<int> chunks = config.oselm_chunks;
  if (chunks.empty()) chunks.push_back(options.oselm_chunk);
  for (int c : chunks) {
    if (c < 1) throw std::invalid_argument("oselm: chunk sizes must be >= 1");
  }
  OnlineSequentialElm os(static_cast<int>(L), 1, options.lambda, options.forgetting);
  os.initialize(H.topRows(n0), T.head(n0));
  const auto t0 = Clock::now();
  Eigen::Index r = n0;
  size_t ci = 0;
  long updates = 0;
  while (r < N) {
    const Eigen::Index n = std::min<Eigen::Index>(chunks[ci++ % chunks.size()], N - r);
    if (n == 1) {
      os.update_one(H.row(r).transpose(), T.segment(r, 1));
    } else {
      os.update(H.middleRows(r, n), T.segment(r, n));
    }
    r += n;
    ++updates;
  }
  if (stats) {
    stats->oselm_updates = updates;
    stats->oselm_update_seconds = seconds_since(t0);
  }
  return os.beta();
}

}  // namespace

Method parse_method(const std::string& name) {
  if (name == "elm") return Method::kElm;
  if (name == "relm") return Method::kRelm;
  if (name == "oselm") return Method::kOselm;
  throw std::invalid_argument("unknown data-driven method '" + name + "' (elm, relm, oselm)");
}

std::string method_name(Method m) {
  switch (m) {
    case Method::kElm: return "elm";
    case Method::kRelm: return "relm";
    case Method::kOselm: return "oselm";
  }
  return "?";
}

std::shared_ptr<const MassModel> MassModel::train(Method method,
                                                  const std::vector<const MassIdRun*>& runs,
                                                  const DataDrivenOptions& options,
                                                  const ModelConfig& config, TrainStats* stats) {
  if (runs.empty()) throw std::invalid_argument(method_name(method) + ": empty training set");
  if (options.hidden_nodes < 1) {
    throw std::invalid_argument(method_name(method) + ": hidden_nodes must be >= 1");
  }
  if (method != Method::kElm && !(options.lambda > 0.0)) {
    throw std::invalid_argument(method_name(method) + ": lambda must be positive");
  }
  TrainStats local;
  TrainStats& st = stats ? *stats : local;
  auto model = std::make_shared<MassModel>();
  model->method_ = method;
  model->config_ = config;

  auto t0 = Clock::now();
  const RunFeatures data = extract_training_set(runs, config.features);
  model->normalizer_ = Normalizer::fit(data.X, data.y);
  const Eigen::MatrixXd X = model->normalizer_.apply(data.X);
  const Eigen::VectorXd T = model->normalizer_.apply_target(data.y);
  st.rows = X.rows();
  st.feature_seconds = seconds_since(t0);

  t0 = Clock::now();
  const int d = config.features.dimension();
  const double scale =
      config.weight_scale > 0.0 ? config.weight_scale : 2.0 / std::sqrt(static_cast<double>(d));
  model->layer_ = HiddenLayer(d, options.hidden_nodes, options.seed, scale);
  const Eigen::MatrixXd H = model->layer_.activations(X);
  switch (method) {
    case Method::kElm: model->beta_ = solve_elm(H, T); break;
    case Method::kRelm: model->beta_ = solve_relm(H, T, options.lambda); break;
    case Method::kOselm: model->beta_ = train_oselm(H, T, options, config, &st); break;
  }
  st.solve_seconds = seconds_since(t0);
  st.weight_norm = model->beta_.norm();
  const Eigen::VectorXd fit = (H * model->beta_).col(0);
  Eigen::ArrayXd rel(fit.size());
  for (Eigen::Index i = 0; i < fit.size(); ++i) {
    rel(i) = (model->normalizer_.invert_target(fit(i)) - data.y(i)) / data.y(i);
  }
  st.train_rmse_percent = 100.0 * std::sqrt(rel.square().mean());
  return model;
}

double MassModel::predict(const Eigen::VectorXd& x_raw) const {
  const Eigen::VectorXd h = layer_.activation(normalizer_.apply_row(x_raw));
  return normalizer_.invert_target(h.dot(beta_.col(0)));
}

std::vector<double> MassModel::predict_run(const MassIdRun& run) const {
  std::vector<double> out(run.samples.size(), run.info.initial_mass_guess);
  const RunFeatures f = extract_run_features(run, config_.features, 1, /*partial_windows=*/true);
  if (f.X.rows() == 0) return out;
  const Eigen::MatrixXd H = layer_.activations(normalizer_.apply(f.X));
  const Eigen::VectorXd y = H * beta_.col(0);
  for (Eigen::Index r = 0; r < y.size(); ++r) {
    out[static_cast<size_t>(f.sample_index[static_cast<size_t>(r)])] =
        normalizer_.invert_target(y(r));
  }
  return out;
}

ElmMassEstimator::ElmMassEstimator(std::shared_ptr<const MassModel> model)
    : model_(std::move(model)), extractor_(model_->config().features, /*partial_windows=*/true) {}

void ElmMassEstimator::reset(const RunInfo& info, const MassIdSample& first) {
  extractor_.reset(info.gravity);
  initial_guess_ = info.initial_mass_guess;
  extractor_.push(first, &x_);
  last_t_ = first.t;
  primed_ = false;
}

double ElmMassEstimator::update(const MassIdSample& sample) {
  // The runner may feed the first sample again after reset(); it is already in the window.
  if (sample.t <= last_t_) return primed_ ? model_->predict(x_) : initial_guess_;
  last_t_ = sample.t;
  if (extractor_.push(sample, &x_)) primed_ = true;
  else return initial_guess_;
  return model_->predict(x_);
}

}  // namespace vid::massid::elm

namespace vid::massid {

std::unique_ptr<MassEstimator> train_data_driven(const std::string& method,
                                                 const std::vector<const MassIdRun*>& training,
                                                 const DataDrivenOptions& options) {
  const elm::Method m = elm::parse_method(method);
  if (training.empty()) throw std::invalid_argument(method + ": empty training set");
  return std::make_unique<elm::ElmMassEstimator>(elm::MassModel::train(m, training, options));
}

}  // namespace vid::massid
