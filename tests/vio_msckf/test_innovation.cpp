/// Fast gate path of the visual update: block-sparse innovation covariance, the split
/// nullspace projector and the projection-free gate statistic must equal the dense reference
/// computations.

#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <string>

#include "synthetic_scene.h"
#include "vio_core/msckf/innovation.h"
#include "vio_core/msckf/linear_algebra.h"

namespace vid::msckf {
namespace {

using testing::make_scene;
using testing::Scene;
using testing::SceneOptions;

Eigen::MatrixXd random_spd(int n, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = 1e-2 * g(rng);
  return B * B.transpose() + 1e-6 * Eigen::MatrixXd::Identity(n, n);
}

/// Observation blocks of the synthetic scene's first track; extrinsic blocks optional.
/// clone_col(i) / ext_col(c) give the compact column of clone i / camera c.
template <typename CloneCol, typename ExtCol>
std::vector<ObservationBlocks> scene_blocks(const Scene& s, bool with_ext, CloneCol clone_col,
                                            ExtCol ext_col) {
  std::vector<ObservationBlocks> out;
  const FeatureTrack& tr = s.tracks[0];
  for (const TrackObservation& o : tr.obs) {
    for (std::size_t i = 0; i < s.clones_true.size(); ++i) {
      const ClonePose& c = s.clones_true[i];
      if (c.t_ns != o.t_ns) continue;
      ProjectionJacobians jac;
      EXPECT_TRUE(project_with_jacobians(c.R_WI, c.p_WI, s.extrinsics[o.cam_id].T_IC,
                                         s.landmarks_W[0], &jac));
      ObservationBlocks ob;
      ob.clone_col = clone_col(static_cast<int>(i));
      ob.ext_col = with_ext ? ext_col(o.cam_id) : -1;
      ob.H_clone = jac.H_clone;
      ob.H_ext = jac.H_extrinsic;
      out.push_back(ob);
    }
  }
  return out;
}

Eigen::MatrixXd dense_H(const std::vector<ObservationBlocks>& obs, int K) {
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * static_cast<int>(obs.size()), K);
  for (std::size_t a = 0; a < obs.size(); ++a) {
    H.block<2, 6>(2 * a, obs[a].clone_col) += obs[a].H_clone;
    if (obs[a].ext_col >= 0) H.block<2, 6>(2 * a, obs[a].ext_col) += obs[a].H_ext;
  }
  return H;
}

void expect_lower_equal(const Eigen::MatrixXd& S, const Eigen::MatrixXd& ref, double rel) {
  ASSERT_EQ(S.rows(), ref.rows());
  ASSERT_EQ(S.cols(), ref.cols());
  const Eigen::MatrixXd diff = S.triangularView<Eigen::Lower>().toDenseMatrix() -
                               ref.triangularView<Eigen::Lower>().toDenseMatrix();
  EXPECT_LT(diff.norm(), rel * ref.norm());
}

class InnovationCovariance : public ::testing::TestWithParam<bool> {};

TEST_P(InnovationCovariance, BlockSparseEqualsDenseProduct) {
  SceneOptions opt;
  opt.num_features = 1;
  opt.stereo = GetParam();
  const Scene s = make_scene(opt);
  const std::size_t cams = opt.stereo ? 2 : 1;
  std::mt19937 rng(21);
  const int nc = opt.num_clones;
  // Layouts: consecutive clones (read in place); extrinsics first then clones; clones in
  // reverse order with a gap (gathered path, unsorted blocks).
  struct Layout {
    bool with_ext;
    int K;
    std::function<int(int)> clone_col;
    std::function<int(int)> ext_col;
  };
  // Without extrinsics the clone-group path is used, with them the general block path.
  const std::vector<Layout> layouts = {
      {false, 6 * nc, [](int i) { return 6 * i; }, [](int) { return -1; }},
      {false, 6 * nc + 6, [nc](int i) { return 6 * (nc - i); }, [](int) { return -1; }},
      {true, 6 * nc + 12, [](int i) { return 12 + 6 * i; }, [](int c) { return 6 * c; }},
      {true, 6 * nc + 18, [nc](int i) { return 6 * (nc - 1 - i); },
       [nc](int c) { return 6 * (nc + 1 + c); }},
  };
  InnovationScratch scratch;  // reused across layouts on purpose
  for (std::size_t l = 0; l < layouts.size(); ++l) {
    const Layout& L = layouts[l];
    const Eigen::MatrixXd P_T = random_spd(L.K, rng);
    const std::vector<ObservationBlocks> obs = scene_blocks(s, L.with_ext, L.clone_col, L.ext_col);
    ASSERT_EQ(obs.size(), cams * nc);
    const Eigen::MatrixXd H = dense_H(obs, L.K);
    const Eigen::MatrixXd ref = H * P_T * H.transpose();
    Eigen::MatrixXd S;
    innovation_covariance_lower(P_T, obs, &S, &scratch);
    SCOPED_TRACE("layout " + std::to_string(l));
    expect_lower_equal(S, ref, 1e-12);

    // A repeated observation makes one clone group larger (general-size group path).
    std::vector<ObservationBlocks> rep = obs;
    rep.insert(rep.begin() + 1, 2, obs[0]);
    const Eigen::MatrixXd H_rep = dense_H(rep, L.K);
    Eigen::MatrixXd S_rep;
    innovation_covariance_lower(P_T, rep, &S_rep, &scratch);
    expect_lower_equal(S_rep, H_rep * P_T * H_rep.transpose(), 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(MonoAndStereo, InnovationCovariance, ::testing::Bool());

TEST(NullspaceProjector, MatchesNullspaceProject) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  NullspaceProjector proj;  // reused across sizes on purpose
  for (int m : {4, 9, 22, 44}) {
    Eigen::MatrixXd H_f(m, 3), H_x(m, 10);
    Eigen::VectorXd r(m);
    for (int i = 0; i < m; ++i) {
      r(i) = g(rng);
      for (int j = 0; j < 3; ++j) H_f(i, j) = g(rng);
      for (int j = 0; j < 10; ++j) H_x(i, j) = g(rng);
    }
    Eigen::MatrixXd H_ref = H_x;
    Eigen::VectorXd r_ref = r;
    nullspace_project(H_f, &H_ref, &r_ref);

    proj.compute(H_f);
    Eigen::MatrixXd H_new = H_x;
    Eigen::VectorXd r_new = r;
    proj.apply(H_new);
    proj.apply(r_new);
    SCOPED_TRACE("m = " + std::to_string(m));
    EXPECT_LT((H_new.bottomRows(m - 3) - H_ref).norm(), 1e-12 * H_ref.norm());
    EXPECT_LT((r_new.tail(m - 3) - r_ref).norm(), 1e-12 * r_ref.norm());
  }
  EXPECT_THROW(proj.compute(Eigen::MatrixXd::Ones(3, 3)), std::invalid_argument);
  EXPECT_THROW(proj.compute(Eigen::MatrixXd::Ones(6, 2)), std::invalid_argument);
}

TEST(ProjectedChi2, EqualsChi2OfProjectedSystem) {
  std::mt19937 rng(8);
  std::normal_distribution<double> g(0.0, 1.0);
  ProjectedChi2 gate;  // reused across sizes on purpose
  for (int m : {4, 9, 22, 44}) {
    // S like the gate's: correlated H P H^T part plus isotropic noise, residual of a
    // triangulated feature (small along H_f) plus noise.
    Eigen::MatrixXd H_f(m, 3), A(m, m);
    Eigen::VectorXd r(m);
    for (int i = 0; i < m; ++i) {
      r(i) = 1e-3 * g(rng);
      for (int j = 0; j < 3; ++j) H_f(i, j) = 0.3 * g(rng);
      for (int j = 0; j < m; ++j) A(i, j) = 1e-2 * g(rng);
    }
    Eigen::MatrixXd S = A * A.transpose();
    S.diagonal().array() += 1e-5;
    // Reference: project r and S with nullspace_project, then the dense chi2.
    Eigen::MatrixXd H_x = Eigen::MatrixXd::Zero(m, 1);
    Eigen::VectorXd r_o = r;
    Eigen::MatrixXd S_o = S;
    nullspace_project(H_f, &H_x, &r_o, &S_o);
    const double ref = r_o.dot(S_o.llt().solve(r_o));

    // Only the lower triangle of S is read: poison the strict upper part.
    Eigen::MatrixXd S_in = S;
    S_in.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);
    double chi2 = -1.0;
    ASSERT_TRUE(gate.compute(S_in, H_f, r, &chi2));
    SCOPED_TRACE("m = " + std::to_string(m));
    EXPECT_GT(ref, 0.0);
    EXPECT_NEAR(chi2, ref, 1e-10 * ref);
  }
  // Not positive definite: rejected, chi2 untouched.
  Eigen::MatrixXd S = -Eigen::MatrixXd::Identity(6, 6);
  double chi2 = 7.0;
  EXPECT_FALSE(gate.compute(S, Eigen::MatrixXd::Ones(6, 3), Eigen::VectorXd::Ones(6), &chi2));
  EXPECT_EQ(chi2, 7.0);
  Eigen::MatrixXd S5 = Eigen::MatrixXd::Identity(5, 5);
  EXPECT_THROW(gate.compute(S5, Eigen::MatrixXd::Ones(4, 3), Eigen::VectorXd::Ones(5), &chi2),
               std::invalid_argument);
}

}  // namespace
}  // namespace vid::msckf
