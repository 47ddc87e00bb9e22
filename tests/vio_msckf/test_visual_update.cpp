/// build_visual_update on a synthetic stereo scene: shape and sparsity of H, linearization
/// (incl. extrinsics and FEJ), chi2 gating, and an EKF update that reduces the clone errors.

#include <gtest/gtest.h>

#include <random>

#include "synthetic_scene.h"
#include "vio_core/chi2.h"
#include "vio_core/msckf/linear_algebra.h"
#include "vio_core/msckf/visual_update.h"

namespace vid::msckf {
namespace {

using testing::make_scene;
using testing::Scene;
using testing::SceneOptions;

constexpr double kFocal = 400.0;

/// Prior: clone 0 known (fixes the gauge), others 0.6 deg / 5 cm (times scale), IMU loose.
Eigen::MatrixXd prior(const Scene& s, int extra = 0, double scale = 1.0) {
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(s.state_dim + extra, s.state_dim + extra);
  P.diagonal().head(15).setConstant(1e-2);
  for (std::size_t i = 0; i < s.clones_true.size(); ++i) {
    const int k = s.clones_true[i].cov_index;
    const double sr = i == 0 ? 1e-5 : 0.01 * scale;
    const double sp = i == 0 ? 1e-5 : 0.05 * scale;
    P.diagonal().segment<3>(k).setConstant(sr * sr);
    P.diagonal().segment<3>(k + 3).setConstant(sp * sp);
  }
  for (int e = 0; e < extra; ++e) P(s.state_dim + e, s.state_dim + e) = 1e-6;
  return P;
}

/// Clones with errors drawn from P (current and first estimates equal).
std::vector<ClonePose> perturbed(const Scene& s, const Eigen::MatrixXd& P, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<ClonePose> out = s.clones_true;
  for (ClonePose& c : out) {
    Eigen::Matrix<double, 6, 1> d;
    for (int k = 0; k < 6; ++k) d(k) = g(rng) * std::sqrt(P(c.cov_index + k, c.cov_index + k));
    c.R_WI = c.R_WI * so3::exp(d.head<3>());
    c.p_WI += d.tail<3>();
    c.R_WI_fej = c.R_WI;
    c.p_WI_fej = c.p_WI;
  }
  return out;
}

/// RMS of [rotation error (rad) ; position error (m)] over clones, separately.
std::pair<double, double> clone_rms(const Scene& s, const std::vector<ClonePose>& est) {
  double er = 0.0;
  double ep = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    er += so3::log(s.clones_true[i].R_WI.transpose() * est[i].R_WI).squaredNorm();
    ep += (est[i].p_WI - s.clones_true[i].p_WI).squaredNorm();
  }
  const double n = static_cast<double>(est.size());
  return {std::sqrt(er / n), std::sqrt(ep / n)};
}

/// One EKF update with (H, r, noise_var I) applied to the clones (Joseph form).
void ekf_update(const VisualLinearSystem& sys, Eigen::MatrixXd* P, std::vector<ClonePose>* clones) {
  const Eigen::MatrixXd& H = sys.H;
  Eigen::MatrixXd S = H * (*P) * H.transpose();
  S.diagonal().array() += sys.noise_var;
  const Eigen::MatrixXd K = (*P) * H.transpose() * S.llt().solve(
      Eigen::MatrixXd::Identity(S.rows(), S.rows()));
  const Eigen::VectorXd dx = K * sys.r;
  const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(P->rows(), P->cols()) - K * H;
  *P = IKH * (*P) * IKH.transpose() + sys.noise_var * K * K.transpose();
  for (ClonePose& c : *clones) {
    c.R_WI = c.R_WI * so3::exp(dx.segment<3>(c.cov_index));
    c.p_WI += dx.segment<3>(c.cov_index + 3);
  }
}

VisualUpdateParams params_for(double sigma_px) {
  VisualUpdateParams p;
  p.sigma_norm = sigma_px / kFocal;
  return p;
}

TEST(VisualUpdate, ShapeSparsityAndZeroResidualAtTruth) {
  SceneOptions opt;
  const Scene s = make_scene(opt);
  const Eigen::MatrixXd P = prior(s);
  const auto sys = build_visual_update(s.tracks, s.clones_true, s.extrinsics, P, params_for(1.0));
  EXPECT_EQ(sys.features_used, opt.num_features);
  EXPECT_EQ(sys.features_rejected_chi2, 0);
  EXPECT_EQ(sys.features_rejected_triangulation, 0);
  EXPECT_EQ(sys.H.cols(), P.cols());
  // 40 x (4 * 11 - 3) rows compressed to the 66 touched columns.
  EXPECT_EQ(sys.H.rows(), 6 * opt.num_clones);
  EXPECT_EQ(sys.r.size(), sys.H.rows());
  EXPECT_DOUBLE_EQ(sys.noise_var, std::pow(1.0 / kFocal, 2));
  EXPECT_EQ(sys.H.leftCols(15).norm(), 0.0);  // IMU block untouched
  EXPECT_GT(sys.H.rightCols(6 * opt.num_clones).norm(), 1.0);
  EXPECT_LT(sys.r.norm(), 1e-9);
  // A visual-only system cannot see a global translation: H annihilates it.
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(P.cols());
  for (const ClonePose& c : s.clones_true) dx.segment<3>(c.cov_index + 3) = Eigen::Vector3d(1, -2, 0.5);
  EXPECT_LT((sys.H * dx).norm(), 1e-9 * sys.H.norm() * dx.norm());
}

TEST(VisualUpdate, LinearizationMatchesPerturbedResidualIncludingExtrinsics) {
  // At the truth with exact observations r = 0; after perturbing the state by dx the
  // nullspace-projected residual must be -H dx to first order (single feature: no QR).
  SceneOptions opt;
  opt.num_features = 1;
  Scene s = make_scene(opt);
  const int n0 = s.state_dim;
  s.extrinsics[0].cov_index = n0;
  s.extrinsics[1].cov_index = n0 + 6;
  const Eigen::MatrixXd P = prior(s, 12);
  const VisualUpdateParams params = params_for(1.0);
  const auto sys0 = build_visual_update(s.tracks, s.clones_true, s.extrinsics, P, params);
  ASSERT_EQ(sys0.features_used, 1);
  ASSERT_EQ(sys0.H.rows(), 4 * opt.num_clones - 3);
  EXPECT_GT(sys0.H.rightCols(12).norm(), 1.0);  // extrinsic columns are filled

  std::mt19937 rng(2);
  std::normal_distribution<double> g(0.0, 1e-5);
  Eigen::VectorXd dx(P.cols());
  for (int k = 0; k < dx.size(); ++k) dx(k) = g(rng);
  dx.head(15).setZero();
  std::vector<ClonePose> clones = s.clones_true;
  for (ClonePose& c : clones) {
    c.R_WI = c.R_WI * so3::exp(dx.segment<3>(c.cov_index));
    c.p_WI += dx.segment<3>(c.cov_index + 3);
    c.R_WI_fej = c.R_WI;
    c.p_WI_fej = c.p_WI;
  }
  std::vector<CameraExtrinsic> ext = s.extrinsics;
  for (CameraExtrinsic& e : ext) {
    e.T_IC.linear() = e.T_IC.linear() * so3::exp(dx.segment<3>(e.cov_index));
    e.T_IC.translation() += dx.segment<3>(e.cov_index + 3);
  }
  const auto sys1 = build_visual_update(s.tracks, clones, ext, P, params);
  ASSERT_EQ(sys1.features_used, 1);
  const Eigen::VectorXd predicted = -sys0.H * dx;
  EXPECT_GT(predicted.norm(), 1e-6);
  EXPECT_LT((sys1.r - predicted).norm(), 1e-3 * predicted.norm());
}

TEST(VisualUpdate, NormalEquationCompressionMatchesQr) {
  for (bool with_extrinsics : {false, true}) {
    SceneOptions opt;
    opt.pixel_sigma_norm = 1.0 / kFocal;
    Scene s = make_scene(opt);
    int extra = 0;
    if (with_extrinsics) {
      s.extrinsics[0].cov_index = s.state_dim;
      s.extrinsics[1].cov_index = s.state_dim + 6;
      extra = 12;
    }
    const Eigen::MatrixXd P = prior(s, extra, 0.2);
    const std::vector<ClonePose> est = perturbed(s, P, 5);
    VisualUpdateParams pq = params_for(1.0);
    VisualUpdateParams pn = pq;
    pn.compression = Compression::kNormalEquations;
    const auto q = build_visual_update(s.tracks, est, s.extrinsics, P, pq);
    const auto ne = build_visual_update(s.tracks, est, s.extrinsics, P, pn);
    EXPECT_EQ(q.features_used, ne.features_used);
    EXPECT_EQ(q.features_rejected_chi2, ne.features_rejected_chi2);
    EXPECT_GT(q.features_used, 30);
    ASSERT_EQ(ne.H.cols(), P.cols());
    EXPECT_LE(ne.H.rows(), q.H.rows());  // gauge directions dropped
    const Eigen::MatrixXd Aq = q.H.transpose() * q.H;
    const Eigen::MatrixXd An = ne.H.transpose() * ne.H;
    const Eigen::VectorXd bq = q.H.transpose() * q.r;
    const Eigen::VectorXd bn = ne.H.transpose() * ne.r;
    EXPECT_LT((Aq - An).norm(), 1e-9 * Aq.norm()) << "extrinsics " << with_extrinsics;
    EXPECT_LT((bq - bn).norm(), 1e-7 * bq.norm()) << "extrinsics " << with_extrinsics;
    // Same EKF correction.
    const auto correction = [&](const VisualLinearSystem& sys) {
      Eigen::MatrixXd Sm = sys.H * P * sys.H.transpose();
      Sm.diagonal().array() += sys.noise_var;
      return Eigen::VectorXd(P * sys.H.transpose() * Sm.ldlt().solve(sys.r));
    };
    const Eigen::VectorXd dq = correction(q);
    EXPECT_LT((dq - correction(ne)).norm(), 1e-6 * dq.norm());
  }
}

TEST(VisualUpdate, JacobiansUseFirstEstimatesResidualsUseCurrentValues) {
  SceneOptions opt;
  opt.num_features = 5;
  const Scene s = make_scene(opt);
  const Eigen::MatrixXd P = prior(s);
  const std::vector<ClonePose> shifted = perturbed(s, P, 9);
  // Current = truth, FEJ = shifted: zero residual, but H differs from the all-truth one.
  std::vector<ClonePose> a = s.clones_true;
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i].R_WI_fej = shifted[i].R_WI;
    a[i].p_WI_fej = shifted[i].p_WI;
  }
  const auto sys_truth = build_visual_update(s.tracks, s.clones_true, s.extrinsics, P, params_for(1));
  const auto sys_fej = build_visual_update(s.tracks, a, s.extrinsics, P, params_for(1));
  ASSERT_EQ(sys_fej.features_used, opt.num_features);
  EXPECT_LT(sys_fej.r.norm(), 1e-9);
  // Compare H^T H (basis independent).
  const Eigen::MatrixXd A0 = sys_truth.H.transpose() * sys_truth.H;
  const Eigen::MatrixXd A1 = sys_fej.H.transpose() * sys_fej.H;
  EXPECT_GT((A0 - A1).norm(), 1e-3 * A0.norm());
  // Current = shifted, FEJ = truth: non-zero residual; H is the all-truth one.
  std::vector<ClonePose> b = shifted;
  for (std::size_t i = 0; i < b.size(); ++i) {
    b[i].R_WI_fej = s.clones_true[i].R_WI;
    b[i].p_WI_fej = s.clones_true[i].p_WI;
  }
  VisualUpdateParams loose = params_for(1);
  loose.chi2_multiplier = 1e6;
  const auto sys_b = build_visual_update(s.tracks, b, s.extrinsics, P, loose);
  ASSERT_EQ(sys_b.features_used, opt.num_features);
  EXPECT_GT(sys_b.r.norm(), 1e-3);
}

TEST(VisualUpdate, EkfUpdateReducesCloneErrors) {
  // Large prior (0.6 deg / 5 cm): one EKF step removes most of the error (it is one
  // Gauss-Newton step, so the linearization error keeps it from being consistent).
  // Small prior (0.12 deg / 1 cm): the step is nearly linear and the remaining error must be
  // consistent with the posterior covariance.
  for (double scale : {1.0, 0.2}) {
    for (double sigma_px : {0.0, 1.0}) {
      SceneOptions opt;
      opt.pixel_sigma_norm = sigma_px / kFocal;
      opt.seed = 4;
      const Scene s = make_scene(opt);
      Eigen::MatrixXd P = prior(s, 0, scale);
      std::vector<ClonePose> est = perturbed(s, P, 21);
      const auto before = clone_rms(s, est);
      // Exact pixels still need a noise floor in the filter.
      const VisualUpdateParams params = params_for(std::max(sigma_px, 0.5));
      const auto sys = build_visual_update(s.tracks, est, s.extrinsics, P, params);
      EXPECT_GE(sys.features_used, opt.num_features - 3) << "sigma " << sigma_px;
      const Eigen::MatrixXd P0 = P;
      ekf_update(sys, &P, &est);
      const auto after = clone_rms(s, est);
      const int k0 = est[1].cov_index;
      const int nk = 6 * (static_cast<int>(est.size()) - 1);
      Eigen::VectorXd e(nk);
      for (std::size_t i = 1; i < est.size(); ++i) {
        e.segment<3>(6 * (i - 1)) = so3::log(s.clones_true[i].R_WI.transpose() * est[i].R_WI);
        e.segment<3>(6 * (i - 1) + 3) = est[i].p_WI - s.clones_true[i].p_WI;
      }
      const double nees = e.dot(P.block(k0, k0, nk, nk).llt().solve(e));
      std::printf("prior x%.1f sigma %.1f px: rot rms %.5f -> %.5f rad, pos rms %.4f -> %.4f m, "
                  "NEES %.1f (dof %d)\n", scale, sigma_px, before.first, after.first,
                  before.second, after.second, nees, nk);
      const std::string tag = "scale " + std::to_string(scale) + " sigma " + std::to_string(sigma_px);
      // Rotation is well observed; position less (stereo scale, 0.11 m baseline). With the
      // small prior, prior and measurements carry comparable information.
      EXPECT_LT(after.first, (scale < 1.0 ? 0.6 : 0.3) * before.first) << tag;
      EXPECT_LT(after.second, (scale < 1.0 ? 0.8 : 0.5) * before.second) << tag;
      if (scale < 1.0) {
        EXPECT_LT(nees, chi2_quantile(0.999, nk)) << tag;
      }
      // The covariance of every perturbed clone shrank.
      for (std::size_t i = 1; i < est.size(); ++i) {
        const int k = est[i].cov_index;
        EXPECT_LT((P.block<6, 6>(k, k).trace()), (P0.block<6, 6>(k, k).trace()));
      }
    }
  }
}

TEST(VisualUpdate, Chi2GateRejectsOutlierTrack) {
  SceneOptions opt;
  opt.num_features = 3;
  const Scene s = make_scene(opt);
  // A tight prior and the true state: the clean tracks pass easily.
  const Eigen::MatrixXd P = prior(s, 0, 0.01);
  std::vector<FeatureTrack> tracks = s.tracks;
  // Feature 1 gets one observation 12 px off: triangulates, fails the gate.
  tracks[1].obs[9].uv_norm += Eigen::Vector2d(12.0, -5.0) / kFocal;
  const auto sys = build_visual_update(tracks, s.clones_true, s.extrinsics, P, params_for(1.0));
  EXPECT_EQ(sys.features_rejected_chi2, 1);
  EXPECT_EQ(sys.features_rejected_triangulation, 0);
  EXPECT_EQ(sys.features_used, 2);
  const auto only = build_visual_update({tracks[1]}, s.clones_true, s.extrinsics, P, params_for(1.0));
  EXPECT_EQ(only.features_rejected_chi2, 1);
  EXPECT_EQ(only.H.rows(), 0);
  EXPECT_EQ(only.H.cols(), P.cols());
  // A huge multiplier lets it through (the gate, not triangulation, rejected it).
  VisualUpdateParams loose = params_for(1.0);
  loose.chi2_multiplier = 100.0;
  EXPECT_EQ(build_visual_update({tracks[1]}, s.clones_true, s.extrinsics, P, loose).features_used, 1);
}

TEST(VisualUpdate, Chi2GateUsesDenseInnovationCovariance) {
  // Single feature (41 rows, no compression): the gate statistic must be
  // r^T (H P H^T + sigma^2 I)^-1 r with the returned (H, r) and a dense, correlated P
  // (extrinsics estimated too). Bracket it with the chi2 multiplier.
  SceneOptions opt;
  opt.num_features = 1;
  opt.pixel_sigma_norm = 1.0 / kFocal;
  Scene s = make_scene(opt);
  s.extrinsics[0].cov_index = s.state_dim;
  s.extrinsics[1].cov_index = s.state_dim + 6;
  const int n = s.state_dim + 12;
  std::mt19937 rng(12);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = 2e-3 * g(rng);
  const Eigen::MatrixXd P = B * B.transpose() + 1e-6 * Eigen::MatrixXd::Identity(n, n);
  const std::vector<ClonePose> est = perturbed(s, prior(s, 12, 0.1), 14);
  VisualUpdateParams loose = params_for(1.0);
  loose.chi2_multiplier = 1e9;
  const auto sys = build_visual_update(s.tracks, est, s.extrinsics, P, loose);
  ASSERT_EQ(sys.features_used, 1);
  const int dof = static_cast<int>(sys.H.rows());
  ASSERT_EQ(dof, 4 * opt.num_clones - 3);
  Eigen::MatrixXd S = sys.H * P * sys.H.transpose();
  S.diagonal().array() += sys.noise_var;
  const double chi2 = sys.r.dot(S.llt().solve(sys.r));
  EXPECT_GT(chi2, 1.0);
  const double ratio = chi2 / chi2_95(dof);
  VisualUpdateParams above = loose;
  above.chi2_multiplier = ratio * (1.0 + 1e-6);
  VisualUpdateParams below = loose;
  below.chi2_multiplier = ratio * (1.0 - 1e-6);
  EXPECT_EQ(build_visual_update(s.tracks, est, s.extrinsics, P, above).features_used, 1);
  EXPECT_EQ(build_visual_update(s.tracks, est, s.extrinsics, P, below).features_rejected_chi2, 1);
}

TEST(VisualUpdate, Chi2RejectionRateMatchesSignificanceWithCorrectNoise) {
  // State error drawn from P, 1 px noise, filter told 1 px: about 5% of features fail the
  // 95% gate. (At the exact state, S = H P H^T + R would overstate the residual spread.)
  SceneOptions opt;
  opt.num_features = 400;
  opt.pixel_sigma_norm = 1.0 / kFocal;
  opt.seed = 8;
  const Scene s = make_scene(opt);
  const Eigen::MatrixXd P = prior(s, 0, 0.05);
  const std::vector<ClonePose> est = perturbed(s, P, 31);
  const auto sys = build_visual_update(s.tracks, est, s.extrinsics, P, params_for(1.0));
  EXPECT_EQ(sys.features_rejected_triangulation, 0);
  const double rate = sys.features_rejected_chi2 / 400.0;
  std::printf("chi2 rejection rate %.3f\n", rate);
  EXPECT_GT(rate, 0.01);
  EXPECT_LT(rate, 0.10);
  // Told 0.5 px while the noise is 1 px: most features fail.
  const auto tight = build_visual_update(s.tracks, est, s.extrinsics, P, params_for(0.5));
  EXPECT_GT(tight.features_rejected_chi2, 300);
}

TEST(VisualUpdate, CountsShortTracksAndIgnoresNonCloneTimes) {
  SceneOptions opt;
  opt.num_features = 2;
  const Scene s = make_scene(opt);
  std::vector<FeatureTrack> tracks = s.tracks;
  tracks[0].obs.resize(2);  // stereo pair at one clone only: below min_observations (3)
  // Observations at a time without clone are ignored, not errors.
  tracks[1].obs.push_back({s.clones_true.back().t_ns + 1, 0, Eigen::Vector2d(5.0, 5.0)});
  const Eigen::MatrixXd P = prior(s);
  const auto sys = build_visual_update(tracks, s.clones_true, s.extrinsics, P, params_for(1.0));
  EXPECT_EQ(sys.features_too_short, 1);
  EXPECT_EQ(sys.features_used, 1);
  EXPECT_LT(sys.r.norm(), 1e-9);
  // Mono: only cam 0 observations -> 2 * 11 - 3 rows.
  std::vector<FeatureTrack> mono = {s.tracks[0]};
  std::erase_if(mono[0].obs, [](const TrackObservation& o) { return o.cam_id == 1; });
  EXPECT_EQ(build_visual_update(mono, s.clones_true, s.extrinsics, P, params_for(1.0)).H.rows(),
            2 * opt.num_clones - 3);
}

TEST(VisualUpdate, RejectsBadInput) {
  SceneOptions opt;
  opt.num_features = 2;
  const Scene s = make_scene(opt);
  const Eigen::MatrixXd P = prior(s);
  std::vector<FeatureTrack> tracks = s.tracks;
  tracks[0].obs[0].cam_id = 2;
  EXPECT_THROW(build_visual_update(tracks, s.clones_true, s.extrinsics, P, params_for(1.0)),
               std::invalid_argument);
  std::vector<ClonePose> clones = s.clones_true;
  clones.back().cov_index = static_cast<int>(P.cols()) - 3;
  EXPECT_THROW(build_visual_update(s.tracks, clones, s.extrinsics, P, params_for(1.0)),
               std::invalid_argument);
  EXPECT_THROW(build_visual_update(s.tracks, s.clones_true, s.extrinsics, P, params_for(0.0)),
               std::invalid_argument);
  // No tracks: an empty system with the right width.
  const auto empty = build_visual_update({}, s.clones_true, s.extrinsics, P, params_for(1.0));
  EXPECT_EQ(empty.H.rows(), 0);
  EXPECT_EQ(empty.H.cols(), P.cols());
}

}  // namespace
}  // namespace vid::msckf
