/// @file swls.cpp
/// @brief Sliding-window least squares on Ceres (docs/model.md eqs. (57)-(59)): one parameter block
/// per window state with a right-perturbation manifold, auto-differentiated residuals from
/// swls_residuals.h, and a Schur-complement marginalization prior.
#include "massid/filters/swls.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <stdexcept>

#include "geometry/so3.h"
#include "massid/filters/mass_change_detector.h"

namespace vid::massid {
namespace {

/// @brief [q, p, v, m] with q ⊞ dtheta = q ⊗ exp(dtheta / 2) (docs/design.md §3).
class QuadStateManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kSwlsAmbient; }
  int TangentSize() const override { return kSwlsTangent; }
  bool Plus(const double* x, const double* delta, double* out) const override {
    const Eigen::Map<const Eigen::Quaterniond> q(x);
    Eigen::Map<Eigen::Quaterniond> q_out(out);
    q_out = so3::boxplus(q, Eigen::Vector3d(delta[0], delta[1], delta[2]));
    for (int i = 0; i < 7; ++i) out[4 + i] = x[4 + i] + delta[3 + i];
    return true;
  }
  bool PlusJacobian(const double* x, double* jac) const override {
    Eigen::Map<Eigen::Matrix<double, 11, 10, Eigen::RowMajor>> J(jac);
    J.setZero();
    const Eigen::Map<const Eigen::Quaterniond> q(x);
    // d(q ⊗ [delta/2, 1]) / d delta: vector rows (q_w I + [q_v]x) / 2, scalar row -q_v^T / 2.
    J.block<3, 3>(0, 0) = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + so3::skew(q.vec()));
    J.block<1, 3>(3, 0) = -0.5 * q.vec().transpose();
    J.block<7, 7>(4, 3).setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* d) const override {
    const Eigen::Map<const Eigen::Quaterniond> qy(y), qx(x);
    const Eigen::Vector3d dth = so3::boxminus(qy, qx);
    for (int i = 0; i < 3; ++i) d[i] = dth(i);
    for (int i = 0; i < 7; ++i) d[3 + i] = y[4 + i] - x[4 + i];
    return true;
  }
  bool MinusJacobian(const double* x, double* jac) const override {
    Eigen::Map<Eigen::Matrix<double, 10, 11, Eigen::RowMajor>> J(jac);
    J.setZero();
    const Eigen::Map<const Eigen::Quaterniond> q(x);
    J.block<3, 3>(0, 0) = 2.0 * (q.w() * Eigen::Matrix3d::Identity() - so3::skew(q.vec()));
    J.block<3, 1>(0, 3) = -2.0 * q.vec();
    J.block<7, 7>(3, 4).setIdentity();
    return true;
  }
};

using DynCost = ceres::AutoDiffCostFunction<SwlsDynamicResidual, 10, kSwlsAmbient, kSwlsAmbient>;
using MeasCost = ceres::AutoDiffCostFunction<SwlsMeasurementResidual, 9, kSwlsAmbient>;
using PriorCost = ceres::AutoDiffCostFunction<SwlsPriorResidual, 10, kSwlsAmbient>;

SwlsMeasurementResidual make_measurement(const MassIdSample& s, const Eigen::Matrix<double, 9, 9>& R) {
  SwlsMeasurementResidual m;
  m.y = QuadrotorMassModel::meas_of(s);
  m.sqrt_info_diag = R.diagonal().cwiseSqrt().cwiseInverse();
  return m;
}

SwlsPriorResidual make_initial_prior(const QuadMassState& x0, const QuadrotorMassModel::StateMat& P0) {
  SwlsPriorResidual p;
  swls_pack(x0, p.x_bar);
  Eigen::LLT<QuadrotorMassModel::StateMat> llt(P0);
  p.J = llt.matrixL().solve(QuadrotorMassModel::StateMat::Identity());
  p.r0.setZero();
  return p;
}

SwlsPreintegration make_preintegration(const ModelBasedTuning& t, const RunInfo& info,
                                       const QuadMassInput& u, double dt) {
  SwlsPreintegration pre;
  const double sm = t.sigma_m_rw_rel * info.initial_mass_guess;
  pre.add(u, dt, t.sigma_theta_rw * t.sigma_theta_rw, t.sigma_p_rw * t.sigma_p_rw,
          t.sigma_v_rw * t.sigma_v_rw, sm * sm, info.initial_mass_guess);
  return pre;
}

}  // namespace

struct SlidingWindowLs::Impl {
  struct Node {
    std::array<double, kSwlsAmbient> x{};
    ceres::CostFunction* meas_cost = nullptr;
    ceres::CostFunction* dyn_cost_to_next = nullptr;  ///< dynamics (this, next)
  };

  ModelBasedTuning tuning;
  RunInfo info;
  QuadrotorMassModel model;
  Eigen::Matrix<double, 9, 9> R;
  QuadStateManifold manifold;
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Options options;
  std::deque<std::unique_ptr<Node>> nodes;
  ceres::CostFunction* prior_cost = nullptr;  ///< prior on nodes.front()
  bool started = false;
  double t_prev = 0.0;
  QuadMassInput u_prev;
  QuadMassState newest;
  int n_marginalized = 0;
  MassChangeDetector detector;

  Impl(const ModelBasedTuning& t, const RunInfo& i)
      : tuning(t), info(i), model(i.gravity),
        detector(t.change_tau_s, t.change_threshold, t.change_holdoff_s) {
    R = measurement_covariance(t, i);
    ceres::Problem::Options po;
    po.enable_fast_removal = true;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem = std::make_unique<ceres::Problem>(po);
    // The window is a chain of 10-dim blocks (~100 unknowns): dense normal equations beat
    // SuiteSparse's per-solve symbolic analysis at this size (bench/massid compares them).
    if (t.swls_linear_solver == "dense_normal_cholesky") {
      options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    } else if (t.swls_linear_solver == "dense_qr") {
      options.linear_solver_type = ceres::DENSE_QR;
    } else if (t.swls_linear_solver == "sparse_normal_cholesky") {
      options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    } else {
      throw std::invalid_argument("swls_linear_solver: unknown solver '" + t.swls_linear_solver + "'");
    }
    options.max_num_iterations = t.swls_max_iterations;
    options.function_tolerance = t.swls_function_tolerance;
    options.parameter_tolerance = std::min(1e-8, t.swls_function_tolerance);
    options.gradient_tolerance = std::min(1e-10, t.swls_function_tolerance);
    options.logging_type = ceres::SILENT;
    options.minimizer_progress_to_stdout = false;
    options.num_threads = 1;
  }

  Node* add_node(const QuadMassState& x, const MassIdSample& s) {
    auto node = std::make_unique<Node>();
    swls_pack(x, node->x.data());
    problem->AddParameterBlock(node->x.data(), kSwlsAmbient, &manifold);
    node->meas_cost = new MeasCost(new SwlsMeasurementResidual(make_measurement(s, R)));
    problem->AddResidualBlock(node->meas_cost, nullptr, node->x.data());
    nodes.push_back(std::move(node));
    return nodes.back().get();
  }

  /// @brief Add J^T J and J^T r of one factor (tangent Jacobians) into H, b over [x0, x1].
  void accumulate(ceres::CostFunction* cost, const std::vector<int>& which, Eigen::Matrix<double, 20, 20>* H,
                  Eigen::Matrix<double, 20, 1>* b) {
    const int nr = cost->num_residuals();
    std::vector<const double*> params;
    for (int w : which) params.push_back(nodes[w]->x.data());
    Eigen::VectorXd r(nr);
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, kSwlsAmbient, Eigen::RowMajor>> Ja(which.size());
    std::vector<double*> jac_ptrs;
    for (auto& J : Ja) {
      J.resize(nr, kSwlsAmbient);
      jac_ptrs.push_back(J.data());
    }
    cost->Evaluate(params.data(), r.data(), jac_ptrs.data());
    Eigen::MatrixXd Jt(nr, 20);
    Jt.setZero();
    for (std::size_t k = 0; k < which.size(); ++k) {
      Eigen::Matrix<double, 11, 10, Eigen::RowMajor> plus_jac;
      manifold.PlusJacobian(params[k], plus_jac.data());
      Jt.middleCols(10 * which[k], 10) = Ja[k] * plus_jac;
    }
    H->noalias() += Jt.transpose() * Jt;
    b->noalias() += Jt.transpose() * r;
  }

  /// @brief Eqs. 22-23: Schur-complement the oldest state into a prior on the next one.
  void marginalize_oldest() {
    Eigen::Matrix<double, 20, 20> H = Eigen::Matrix<double, 20, 20>::Zero();
    Eigen::Matrix<double, 20, 1> b = Eigen::Matrix<double, 20, 1>::Zero();
    accumulate(prior_cost, {0}, &H, &b);
    accumulate(nodes[0]->meas_cost, {0}, &H, &b);
    accumulate(nodes[0]->dyn_cost_to_next, {0, 1}, &H, &b);
    const Eigen::Matrix<double, 10, 10> H00 = H.topLeftCorner<10, 10>();
    const Eigen::LDLT<Eigen::Matrix<double, 10, 10>> ldlt(H00);
    const Eigen::Matrix<double, 10, 10> Hm =
        H.bottomRightCorner<10, 10>() - H.block<10, 10>(10, 0) * ldlt.solve(H.block<10, 10>(0, 10));
    const Eigen::Matrix<double, 10, 1> bm =
        b.tail<10>() - H.block<10, 10>(10, 0) * ldlt.solve(b.head<10>());
    // Hm = U diag(l) U^T -> J = diag(sqrt l) U^T, r0 = diag(1/sqrt l) U^T bm.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 10, 10>> es(0.5 * (Hm + Hm.transpose()));
    const double eps = 1e-12 * std::max(1.0, es.eigenvalues().maxCoeff());
    Eigen::Matrix<double, 10, 1> s = es.eigenvalues().cwiseMax(0.0);
    Eigen::Matrix<double, 10, 1> s_inv;
    for (int i = 0; i < 10; ++i) s_inv(i) = s(i) > eps ? 1.0 / std::sqrt(s(i)) : 0.0;
    auto* prior = new SwlsPriorResidual;
    std::copy(nodes[1]->x.begin(), nodes[1]->x.end(), prior->x_bar);
    prior->J = s.cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
    prior->r0 = s_inv.asDiagonal() * (es.eigenvectors().transpose() * bm);
    // Removing the block drops its prior, measurement and dynamic residuals.
    problem->RemoveParameterBlock(nodes[0]->x.data());
    nodes.pop_front();
    prior_cost = new PriorCost(prior);
    problem->AddResidualBlock(prior_cost, nullptr, nodes[0]->x.data());
    ++n_marginalized;
  }

  const QuadMassState& add_sample(const MassIdSample& s) {
    if (!started) {
      const QuadMassState x0 = initial_state(info, s);
      Node* n = add_node(x0, s);
      prior_cost = new PriorCost(new SwlsPriorResidual(make_initial_prior(x0, initial_covariance(tuning, info))));
      problem->AddResidualBlock(prior_cost, nullptr, n->x.data());
      started = true;
      t_prev = s.t;
      u_prev = QuadrotorMassModel::input_of(s);
      newest = x0;
      return newest;
    }
    const double dt = s.t - t_prev;
    if (!(dt > 0.0)) return newest;  // repeated or out-of-order sample: nothing new
    SwlsPreintegration pre = make_preintegration(tuning, info, u_prev, dt);
    Node* prev = nodes.back().get();
    const QuadMassState guess = model.propagate(swls_unpack(prev->x.data()), u_prev, dt);
    if (tuning.mass_change_detection) {
      // Same detector as the filters; predicted velocity variance ~ one step of random walk.
      const double pv = tuning.sigma_v_rw * tuning.sigma_v_rw * dt;
      const double nu = thrust_axis_innovation(guess, pv * Eigen::Matrix3d::Identity(), s.v_WI,
                                               std::sqrt(R(6, 6)));
      if (detector.update(s.t, dt, nu)) {
        const double sm = tuning.change_sigma_rel * guess.mass_kg;
        pre.mass_var += sm * sm;  // let the mass jump on this interval
      }
    }
    Node* n = add_node(guess, s);
    prev->dyn_cost_to_next = new DynCost(new SwlsDynamicResidual(pre, info.gravity));
    problem->AddResidualBlock(prev->dyn_cost_to_next, nullptr, prev->x.data(), n->x.data());
    if (static_cast<int>(nodes.size()) > tuning.swls_window) marginalize_oldest();
    ceres::Solver::Summary summary;
    ceres::Solve(options, problem.get(), &summary);
    t_prev = s.t;
    u_prev = QuadrotorMassModel::input_of(s);
    newest = swls_unpack(nodes.back()->x.data());
    return newest;
  }
};

SlidingWindowLs::SlidingWindowLs(const ModelBasedTuning& tuning, const RunInfo& info)
    : impl_(std::make_unique<Impl>(tuning, info)) {}
SlidingWindowLs::~SlidingWindowLs() = default;

const QuadMassState& SlidingWindowLs::add_sample(const MassIdSample& s) { return impl_->add_sample(s); }

std::vector<QuadMassState> SlidingWindowLs::window_states() const {
  std::vector<QuadMassState> out;
  for (const auto& n : impl_->nodes) out.push_back(swls_unpack(n->x.data()));
  return out;
}

int SlidingWindowLs::marginalized() const { return impl_->n_marginalized; }

void SlidingWindowLs::build_residuals(const ModelBasedTuning& tuning, const RunInfo& info,
                                      const std::vector<MassIdSample>& samples,
                                      SwlsPriorResidual* prior,
                                      std::vector<SwlsDynamicResidual>* dynamics,
                                      std::vector<SwlsMeasurementResidual>* measurements) {
  const Eigen::Matrix<double, 9, 9> R = measurement_covariance(tuning, info);
  *prior = make_initial_prior(initial_state(info, samples.front()), initial_covariance(tuning, info));
  dynamics->clear();
  measurements->clear();
  for (std::size_t k = 0; k < samples.size(); ++k) {
    measurements->push_back(make_measurement(samples[k], R));
    if (k > 0) {
      const double dt = samples[k].t - samples[k - 1].t;
      dynamics->emplace_back(
          make_preintegration(tuning, info, QuadrotorMassModel::input_of(samples[k - 1]), dt),
          info.gravity);
    }
  }
}

namespace {

class SwlsEstimator final : public MassEstimator {
 public:
  explicit SwlsEstimator(const ModelBasedTuning& t) : tuning_(t) {}
  std::string name() const override { return "swls"; }
  void reset(const RunInfo& info, const MassIdSample& first) override {
    window_ = std::make_unique<SlidingWindowLs>(tuning_, info);
    window_->add_sample(first);
  }
  double update(const MassIdSample& s) override { return window_->add_sample(s).mass_kg; }

 private:
  ModelBasedTuning tuning_;
  std::unique_ptr<SlidingWindowLs> window_;
};

}  // namespace

std::unique_ptr<MassEstimator> make_swls_estimator(const ModelBasedTuning& tuning) {
  return std::make_unique<SwlsEstimator>(tuning);
}

}  // namespace vid::massid
