/// @file tuning.cpp
/// @brief Noise covariances of the model-based methods (docs/model.md eq. (49): n_x, n_y).
#include "massid/filters/tuning.h"

#include <algorithm>

namespace vid::massid {

QuadrotorMassModel::StateMat process_covariance(const ModelBasedTuning& t, double mass_guess,
                                                double dt) {
  using namespace qm_idx;
  QuadrotorMassModel::StateMat Q = QuadrotorMassModel::StateMat::Zero();
  const double sm = t.sigma_m_rw_rel * mass_guess;
  Q.diagonal().segment<3>(kTheta).setConstant(t.sigma_theta_rw * t.sigma_theta_rw * dt);
  Q.diagonal().segment<3>(kP).setConstant(t.sigma_p_rw * t.sigma_p_rw * dt);
  Q.diagonal().segment<3>(kV).setConstant(t.sigma_v_rw * t.sigma_v_rw * dt);
  Q(kM, kM) = sm * sm * dt;
  return Q;
}

Eigen::Matrix<double, 9, 9> measurement_covariance(const ModelBasedTuning& t, const RunInfo& info) {
  const double sq = std::max(info.sigma_q, t.min_sigma_q);
  const double sp = std::max(info.sigma_p, t.min_sigma_p);
  const double sv = std::max(info.sigma_v, t.min_sigma_v);
  Eigen::Matrix<double, 9, 9> R = Eigen::Matrix<double, 9, 9>::Zero();
  R.diagonal().segment<3>(0).setConstant(sq * sq);
  R.diagonal().segment<3>(3).setConstant(sp * sp);
  R.diagonal().segment<3>(6).setConstant(sv * sv);
  return R;
}

QuadrotorMassModel::StateMat initial_covariance(const ModelBasedTuning& t, const RunInfo& info) {
  QuadrotorMassModel::StateMat P = QuadrotorMassModel::StateMat::Zero();
  P.topLeftCorner<9, 9>() = measurement_covariance(t, info);
  const double sm = t.sigma_m0_rel * info.initial_mass_guess;
  P(qm_idx::kM, qm_idx::kM) = sm * sm;
  return P;
}

QuadMassState initial_state(const RunInfo& info, const MassIdSample& first) {
  QuadMassState x;
  x.q_WI = first.q_WI.normalized();
  x.p_WI = first.p_WI;
  x.v_WI = first.v_WI;
  x.mass_kg = info.initial_mass_guess;
  return x;
}

}  // namespace vid::massid
