/// @file vio_filter.cpp
/// @brief The study method "vio": vio_core's FilterState, propagate and ekf_update_columns fed
/// one study sample at a time (vio_filter.h).
#include "massid/filters/vio_filter.h"

#include <stdexcept>
#include <vector>

#include "geometry/so3.h"
#include "types/time.h"
#include "vio_core/ekf_update.h"
#include "vio_core/initializer.h"

namespace vid::massid {

EstimatorParams vio_params_for_study() {
  EstimatorParams p;
  p.mode = PropagationMode::kDynamics;
  p.force_frame = ForceFrame::kBody;
  p.force_rate_random_walk = 0.0;
  p.thrust_scale_random_walk = 0.02;
  p.gyro_random_walk = 0.0;
  p.accel_random_walk = 0.0;
  p.init_sigma_gyro_bias = 0.0;
  p.init_sigma_accel_bias = 0.0;
  return p;
}

ImuInterval vio_interval(const QuadMassInput& u, double mass_guess, double dt) {
  ImuInterval in;
  in.dt = dt;
  in.gyro0 = in.gyro1 = u.w_I;
  in.drive0 = in.drive1 = Eigen::Vector3d(0.0, 0.0, u.thrust_N / mass_guess);
  return in;
}

ImuState vio_state(const QuadMassState& x, double mass_guess) {
  ImuState s;
  s.T_WI.q = x.q_WI;
  s.T_WI.p = x.p_WI;
  s.v_WI = x.v_WI;
  s.thrust_scale = mass_guess / x.mass_kg;
  return s;
}

namespace {

class VioEstimator final : public MassEstimator {
 public:
  VioEstimator(const EstimatorParams& params, const ModelBasedTuning& tuning)
      : params_(params), tuning_(tuning), state_(params) {}
  std::string name() const override { return "vio"; }

  void reset(const RunInfo& info, const MassIdSample& first) override {
    params_.gravity = info.gravity;
    m0_ = info.initial_mass_guess;
    R_ = measurement_covariance(tuning_, info);
    state_ = FilterState(params_);
    const ImuState x0 = vio_state(initial_state(info, first), m0_);
    // The estimator's own prior (biases, force, scale from params), with pose and velocity as
    // measured (the study filters' P0).
    Eigen::MatrixXd P0 = vid::initial_covariance(params_, x0.T_WI.q);
    P0.topLeftCorner<9, 9>() = R_;
    state_.initialize(seconds_to_ns(first.t), x0, P0);
    last_t_ = first.t;
    u_ = QuadrotorMassModel::input_of(first);
  }

  double update(const MassIdSample& s) override {
    const double dt = s.t - last_t_;
    // The first sample (already used by reset) or a repeated time brings nothing new.
    if (!(dt > 0.0)) return mass();
    propagate(state_, vio_interval(u_, m0_, dt), params_);
    const ImuState& x = state_.imu();
    Eigen::VectorXd r(9);
    r << so3::boxminus(s.q_WI.normalized(), x.T_WI.q), s.p_WI - x.T_WI.p, s.v_WI - x.v_WI;
    ekf_update_columns(state_, kMeasCols, Eigen::MatrixXd::Identity(9, 9), r, R_);
    last_t_ = s.t;
    u_ = QuadrotorMassModel::input_of(s);
    return mass();
  }

 private:
  double mass() const { return m0_ / state_.imu().thrust_scale; }

  /// theta, p, v: the measurement's columns (imu_idx::kTheta..kV + 2).
  inline static const std::vector<int> kMeasCols = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  EstimatorParams params_;
  ModelBasedTuning tuning_;
  FilterState state_;
  Eigen::Matrix<double, 9, 9> R_;
  double m0_ = 1.0;
  double last_t_ = 0.0;
  QuadMassInput u_;
};

}  // namespace

std::unique_ptr<MassEstimator> make_vio_estimator(const EstimatorParams& params, const ModelBasedTuning& tuning) {
  if (params.mode != PropagationMode::kDynamics || !(params.thrust_scale_random_walk > 0.0)) {
    throw std::invalid_argument("vio: needs dynamics mode with the thrust scale (thrust_scale_random_walk > 0)");
  }
  return std::make_unique<VioEstimator>(params, tuning);
}

}  // namespace vid::massid
