/// @file estimators.cpp
/// @brief MassEstimator adapters: the generic EKF / UKF (on QuadrotorMassModel), the window
/// MSCKF and SWLS, fed one study sample at a time. The input of sample k is held over
/// [t_k, t_{k+1}] (zero-order hold of the commands).
#include "massid/filters/estimators.h"

#include <deque>
#include <stdexcept>

#include <cmath>

#include "massid/filters/ekf.h"
#include "massid/filters/mass_change_detector.h"
#include "massid/filters/msckf.h"
#include "massid/filters/swls.h"
#include "massid/filters/ukf.h"
#include "massid/filters/vio_filter.h"

namespace vid::massid {
namespace {

/// @brief Shared bookkeeping: time step, held input, noise matrices.
template <class Filter>
class FilterAdapter : public MassEstimator {
 public:
  FilterAdapter(std::string name, const ModelBasedTuning& tuning) : name_(std::move(name)), tuning_(tuning) {}
  std::string name() const override { return name_; }

  void reset(const RunInfo& info, const MassIdSample& first) override {
    info_ = info;
    model_ = QuadrotorMassModel(info.gravity);
    R_ = measurement_covariance(tuning_, info);
    make_filter();
    filter_->init(initial_state(info, first), initial_covariance(tuning_, info));
    last_t_ = first.t;
    u_ = QuadrotorMassModel::input_of(first);
    const bool window = name_ == "msckf";
    rewind_samples_ = window ? 0 : tuning_.change_rewind_samples;
    history_.clear();
    detector_ = MassChangeDetector(window ? tuning_.msckf_change_tau_s : tuning_.change_tau_s,
                                   window ? tuning_.msckf_change_threshold : tuning_.change_threshold,
                                   tuning_.change_holdoff_s);
  }

  double update(const MassIdSample& s) override {
    const double dt = s.t - last_t_;
    // The first sample (already used by reset) or a repeated time brings nothing new.
    if (!(dt > 0.0)) return filter_->state().mass_kg;
    const QuadMassMeas y = QuadrotorMassModel::meas_of(s);
    if (rewind_samples_ > 0) {
      // Fixed-lag history: the filter before this sample's predict, its input, step, measurement.
      if (static_cast<int>(history_.size()) == rewind_samples_) history_.pop_front();
      history_.push_back(Step{*filter_, u_, dt, y});
    }
    filter_->predict(u_, dt, process_covariance(tuning_, info_.initial_mass_guess, dt));
    if (tuning_.mass_change_detection) {
      const QuadrotorMassModel::StateMat P = filter_->covariance();
      const double nu = thrust_axis_innovation(filter_->state(), P.block<3, 3>(qm_idx::kV, qm_idx::kV),
                                               y.v_WI, std::sqrt(R_(6, 6)));
      if (detector_.update(s.t, dt, nu)) {
        const double sm = tuning_.change_sigma_rel * filter_->state().mass_kg;
        QuadrotorMassModel::StateMat dQ = QuadrotorMassModel::StateMat::Zero();
        dQ(qm_idx::kM, qm_idx::kM) = sm * sm;
        if (rewind_samples_ > 0) {
          // The step happened about one detector time constant ago: restart from the filter as
          // it was then with the inflated mass variance and re-apply the samples since (causal:
          // only measurements up to now), instead of inflating after the bias was absorbed.
          *filter_ = history_.front().filter;
          filter_->add_covariance(dQ);
          for (std::size_t j = 0; j + 1 < history_.size(); ++j) {
            const Step& h = history_[j];
            filter_->predict(h.u, h.dt, process_covariance(tuning_, info_.initial_mass_guess, h.dt));
            correct(h.y);
          }
          filter_->predict(u_, dt, process_covariance(tuning_, info_.initial_mass_guess, dt));
          history_.clear();
        } else {
          filter_->add_covariance(dQ);
        }
      }
    }
    correct(y);
    last_t_ = s.t;
    u_ = QuadrotorMassModel::input_of(s);
    return filter_->state().mass_kg;
  }

 protected:
  virtual void make_filter() = 0;
  void correct(const QuadMassMeas& y) { filter_->update(y, R_); }

  std::string name_;
  ModelBasedTuning tuning_;
  RunInfo info_;
  QuadrotorMassModel model_;
  Eigen::Matrix<double, 9, 9> R_;
  std::unique_ptr<Filter> filter_;
  struct Step {
    Filter filter;
    QuadMassInput u;
    double dt;
    QuadMassMeas y;
  };
  int rewind_samples_ = 0;  ///< fixed-lag replay after a detected step (0: inflate only)
  std::deque<Step> history_;
  double last_t_ = 0.0;
  QuadMassInput u_;
  MassChangeDetector detector_;
};

class EkfEstimator final : public FilterAdapter<ManifoldEkf<QuadrotorMassModel>> {
 public:
  explicit EkfEstimator(const ModelBasedTuning& t) : FilterAdapter("ekf", t) {}
  void make_filter() override { filter_ = std::make_unique<ManifoldEkf<QuadrotorMassModel>>(model_); }
};

class UkfEstimator final : public FilterAdapter<ManifoldUkf<QuadrotorMassModel>> {
 public:
  explicit UkfEstimator(const ModelBasedTuning& t) : FilterAdapter("ukf", t) {}
  void make_filter() override { filter_ = std::make_unique<ManifoldUkf<QuadrotorMassModel>>(model_); }
};

class MsckfEstimator final : public FilterAdapter<WindowMsckf> {
 public:
  explicit MsckfEstimator(const ModelBasedTuning& t) : FilterAdapter("msckf", t) {}
  void make_filter() override { filter_ = std::make_unique<WindowMsckf>(model_, tuning_.msckf_window); }
};

}  // namespace

std::vector<std::string> model_based_methods() { return {"ekf", "ukf", "msckf", "swls", "vio"}; }

std::unique_ptr<MassEstimator> make_model_based_estimator(const std::string& method,
                                                          const ModelBasedTuning& tuning) {
  if (method == "ekf") return std::make_unique<EkfEstimator>(tuning);
  if (method == "ukf") return std::make_unique<UkfEstimator>(tuning);
  if (method == "msckf") return std::make_unique<MsckfEstimator>(tuning);
  if (method == "swls") return make_swls_estimator(tuning);
  if (method == "vio") return make_vio_estimator(vio_params_for_study(), tuning);
  throw std::invalid_argument("unknown model-based method '" + method +
                              "' (expected ekf, ukf, msckf, swls or vio)");
}

}  // namespace vid::massid
