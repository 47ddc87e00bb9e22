/// @file visual_update.cpp
/// @brief Per-feature triangulation, FEJ linearization, left-nullspace projection and chi2
/// gate, then stacking and QR compression into one linear system.

#include "vio_core/msckf/visual_update.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "vio_core/chi2.h"
#include "vio_core/msckf/innovation.h"
#include "vio_core/msckf/linear_algebra.h"
#include "vio_core/msckf/projection.h"
#include "vio_core/msckf/triangulation.h"

namespace vid::msckf {
namespace {

/// One usable observation: which clone, which camera, the measurement.
struct ObsRef {
  int clone = 0;
  int cam = 0;
  Eigen::Vector2d uv;
};

/// Columns of the compact system: a 6-column block per touched clone / estimated extrinsic.
struct CompactLayout {
  std::vector<int> clone_offset;  ///< per clone, -1 if untouched
  std::vector<int> ext_offset;    ///< per camera, -1 if not estimated or untouched
  std::vector<int> block_cov;     ///< cov_index of each compact block
  int cols() const { return 6 * static_cast<int>(block_cov.size()); }
};

[[noreturn]] void bad_input(const std::string& what) {
  throw std::invalid_argument(std::string(__FILE__) + ": build_visual_update: " + what);
}

void check_inputs(const std::vector<ClonePose>& clones,
                  const std::vector<CameraExtrinsic>& extrinsics, const Eigen::MatrixXd& P,
                  const VisualUpdateParams& params) {
  const Eigen::Index n = P.cols();
  if (P.rows() != n) bad_input("P is not square");
  for (std::size_t i = 0; i < clones.size(); ++i) {
    if (clones[i].cov_index < 0 || clones[i].cov_index + 6 > n) {
      bad_input("clone " + std::to_string(i) + " cov_index " +
                std::to_string(clones[i].cov_index) + " does not fit P of size " +
                std::to_string(n));
    }
  }
  for (std::size_t c = 0; c < extrinsics.size(); ++c) {
    if (extrinsics[c].cov_index >= 0 && extrinsics[c].cov_index + 6 > n) {
      bad_input("camera " + std::to_string(c) + " extrinsic cov_index " +
                std::to_string(extrinsics[c].cov_index) + " does not fit P of size " +
                std::to_string(n));
    }
  }
  if (!(params.sigma_norm > 0.0)) bad_input("sigma_norm must be > 0");
  if (!(params.chi2_multiplier > 0.0)) bad_input("chi2_multiplier must be > 0");
}

}  // namespace

VisualLinearSystem build_visual_update(const std::vector<FeatureTrack>& tracks,
                                       const std::vector<ClonePose>& clones,
                                       const std::vector<CameraExtrinsic>& extrinsics,
                                       const Eigen::MatrixXd& P,
                                       const VisualUpdateParams& params) {
  check_inputs(clones, extrinsics, P, params);
  const double sigma2 = params.sigma_norm * params.sigma_norm;
  VisualLinearSystem out;
  out.noise_var = sigma2;

  std::unordered_map<TimeNs, int> clone_of_time;
  for (std::size_t i = 0; i < clones.size(); ++i) {
    clone_of_time.emplace(clones[i].t_ns, static_cast<int>(i));
  }

  // Pass 1: usable observations per track and the touched columns.
  std::vector<std::vector<ObsRef>> obs_of(tracks.size());
  std::vector<char> clone_used(clones.size(), 0);
  std::vector<char> ext_used(extrinsics.size(), 0);
  for (std::size_t f = 0; f < tracks.size(); ++f) {
    for (const TrackObservation& o : tracks[f].obs) {
      if (o.cam_id < 0 || o.cam_id >= static_cast<int>(extrinsics.size())) {
        bad_input("feature " + std::to_string(tracks[f].feature_id) + " observed by cam " +
                  std::to_string(o.cam_id) + " but only " + std::to_string(extrinsics.size()) +
                  " extrinsics given");
      }
      const auto it = clone_of_time.find(o.t_ns);
      if (it == clone_of_time.end()) continue;
      obs_of[f].push_back({it->second, o.cam_id, o.uv_norm});
    }
    // Anchor = earliest observation (then lowest cam id).
    std::stable_sort(obs_of[f].begin(), obs_of[f].end(), [&](const ObsRef& a, const ObsRef& b) {
      const TimeNs ta = clones[a.clone].t_ns;
      const TimeNs tb = clones[b.clone].t_ns;
      return ta != tb ? ta < tb : a.cam < b.cam;
    });
    if (static_cast<int>(obs_of[f].size()) < std::max(params.min_observations, 2)) {
      ++out.features_too_short;
      obs_of[f].clear();
      continue;
    }
    for (const ObsRef& o : obs_of[f]) {
      clone_used[o.clone] = 1;
      if (extrinsics[o.cam].cov_index >= 0) ext_used[o.cam] = 1;
    }
  }

  CompactLayout layout;
  layout.clone_offset.assign(clones.size(), -1);
  layout.ext_offset.assign(extrinsics.size(), -1);
  {
    // Blocks in cov_index order so the compact system is a column subset of P.
    std::vector<std::pair<int, int>> blocks;  // (cov_index, clone i or -(cam + 1))
    for (std::size_t i = 0; i < clones.size(); ++i) {
      if (clone_used[i]) blocks.emplace_back(clones[i].cov_index, static_cast<int>(i));
    }
    for (std::size_t c = 0; c < extrinsics.size(); ++c) {
      if (ext_used[c]) blocks.emplace_back(extrinsics[c].cov_index, -static_cast<int>(c) - 1);
    }
    std::sort(blocks.begin(), blocks.end());
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      if (b > 0 && blocks[b].first < blocks[b - 1].first + 6) {
        bad_input("covariance blocks overlap at cov_index " + std::to_string(blocks[b].first));
      }
      const int off = 6 * static_cast<int>(b);
      if (blocks[b].second >= 0) {
        layout.clone_offset[blocks[b].second] = off;
      } else {
        layout.ext_offset[-blocks[b].second - 1] = off;
      }
      layout.block_cov.push_back(blocks[b].first);
    }
  }
  const int K = layout.cols();
  const int n = static_cast<int>(P.cols());
  if (K == 0) {
    out.H.resize(0, n);
    out.r.resize(0);
    return out;
  }
  Eigen::MatrixXd P_T(K, K);
  for (std::size_t a = 0; a < layout.block_cov.size(); ++a) {
    for (std::size_t b = 0; b < layout.block_cov.size(); ++b) {
      P_T.block<6, 6>(6 * a, 6 * b) = P.block<6, 6>(layout.block_cov[a], layout.block_cov[b]);
    }
  }

  const bool use_qr = params.compression == Compression::kQr;
  int max_rows = 0;
  for (const auto& obs : obs_of) {
    if (!obs.empty()) max_rows += 2 * static_cast<int>(obs.size()) - 3;
  }
  Eigen::MatrixXd H_stack(use_qr ? max_rows : 0, K);
  Eigen::VectorXd r_stack(use_qr ? max_rows : 0);
  int rows = 0;
  // Normal equations (lower triangle) for Compression::kNormalEquations.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(use_qr ? 0 : K, use_qr ? 0 : K);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(use_qr ? 0 : K);
  // Per used feature, the 3 columns F L^-T of its term F M^-1 F^T (rows at its blocks).
  int num_candidates = 0;
  for (const auto& obs : obs_of) num_candidates += obs.empty() ? 0 : 1;
  Eigen::MatrixXd F_all(use_qr ? 0 : K, use_qr ? 0 : 3 * num_candidates);

  // Buffers reused across features (no per-feature allocation once warmed up).
  std::vector<CameraRay> rays;
  std::vector<ObservationBlocks> blocks;
  InnovationScratch scratch;
  NullspaceProjector projector;
  ProjectedChi2 gate;
  Eigen::MatrixXd H_x, H_f, S;
  Eigen::Matrix<double, Eigen::Dynamic, 3> G;
  Eigen::VectorXd r, r_o;
  for (std::size_t f = 0; f < tracks.size(); ++f) {
    const std::vector<ObsRef>& obs = obs_of[f];
    if (obs.empty()) continue;
    const int m = static_cast<int>(obs.size());

    // Triangulate with the current clone values.
    rays.resize(m);
    for (int a = 0; a < m; ++a) {
      const ClonePose& c = clones[obs[a].clone];
      const Eigen::Isometry3d& T_IC = extrinsics[obs[a].cam].T_IC;
      rays[a].R_WC = c.R_WI * T_IC.linear();
      rays[a].p_WC = c.p_WI + c.R_WI * T_IC.translation();
      rays[a].uv_norm = obs[a].uv;
    }
    const TriangulationResult tri = triangulate(rays, params.triangulation);
    if (!tri.ok()) {
      ++out.features_rejected_triangulation;
      continue;
    }

    // Residuals at current values, Jacobians at first estimates.
    H_f.resize(2 * m, 3);
    r.resize(2 * m);
    blocks.resize(m);
    bool ok = true;
    for (int a = 0; a < m && ok; ++a) {
      const ClonePose& c = clones[obs[a].clone];
      const Eigen::Isometry3d& T_IC = extrinsics[obs[a].cam].T_IC;
      Eigen::Vector2d z;
      ProjectionJacobians jac;
      ok = project_point(c.R_WI, c.p_WI, T_IC, tri.p_W, &z) &&
           project_with_jacobians(c.R_WI_fej, c.p_WI_fej, T_IC, tri.p_W, &jac);
      if (!ok) break;
      r.segment<2>(2 * a) = obs[a].uv - z;
      H_f.middleRows<2>(2 * a) = jac.H_feature;
      blocks[a].clone_col = layout.clone_offset[obs[a].clone];
      blocks[a].ext_col = layout.ext_offset[obs[a].cam];
      blocks[a].H_clone = jac.H_clone;
      blocks[a].H_ext = jac.H_extrinsic;
    }
    if (!ok) {
      ++out.features_rejected_triangulation;
      continue;
    }

    // Gate: chi2 = r_o^T (Q2^T S Q2)^-1 r_o with S = H_x P_T H_x^T + sigma^2 I from the block
    // structure of H_x (lower triangle only), evaluated without projecting (ProjectedChi2).
    const int dof = 2 * m - 3;
    innovation_covariance_lower(P_T, blocks, &S, &scratch);
    S.diagonal().array() += sigma2;
    double chi2 = 0.0;
    if (!gate.compute(S, H_f, r, &chi2)) {
      ++out.features_rejected_chi2;
      continue;
    }
    if (!(chi2 <= params.chi2_multiplier * chi2_95(dof))) {
      ++out.features_rejected_chi2;
      continue;
    }
    ++out.features_used;
    out.chi2_sum += chi2;
    out.dof_sum += dof;
    if (use_qr) {
      // Left-nullspace projection of H_x (only the QR path needs the rows themselves).
      H_x.setZero(2 * m, K);
      for (int a = 0; a < m; ++a) {
        H_x.block<2, 6>(2 * a, blocks[a].clone_col) = blocks[a].H_clone;
        if (blocks[a].ext_col >= 0) H_x.block<2, 6>(2 * a, blocks[a].ext_col) = blocks[a].H_ext;
      }
      projector.compute(H_f);
      projector.apply(H_x);
      r_o = r;
      projector.apply(r_o);
      H_stack.middleRows(rows, dof) = H_x.bottomRows(dof);
      r_stack.segment(rows, dof) = r_o.tail(dof);
      rows += dof;
      continue;
    }

    // Normal equations of the projected rows without forming them:
    // H_o^T H_o = H_x^T H_x - F M^-1 F^T, H_o^T r_o = H_x^T r_perp, with F = H_x^T H_f,
    // M = H_f^T H_f and r_perp = r - H_f M^-1 H_f^T r (N N^T = I - H_f M^-1 H_f^T).
    // F only has rows at the feature's blocks (scratch.block_col), kept compact in G.
    const Eigen::Matrix3d M = H_f.transpose() * H_f;
    const Eigen::LLT<Eigen::Matrix3d> mllt(M);
    const Eigen::VectorXd r_perp = r - H_f * mllt.solve(H_f.transpose() * r);
    const int nb = static_cast<int>(scratch.block_col.size());
    G.setZero(6 * nb, 3);
    for (int a = 0; a < m; ++a) {
      const ObservationBlocks& ob = blocks[a];
      const int co = ob.clone_col;
      const int eo = ob.ext_col;
      const auto& Jc = ob.H_clone;
      const auto Jf = H_f.middleRows<2>(2 * a);
      A.block<6, 6>(co, co).noalias() += Jc.transpose() * Jc;
      G.middleRows<6>(6 * scratch.local_clone[a]).noalias() += Jc.transpose() * Jf;
      b.segment<6>(co).noalias() += Jc.transpose() * r_perp.segment<2>(2 * a);
      if (eo >= 0) {
        const auto& Je = ob.H_ext;
        A.block<6, 6>(eo, eo).noalias() += Je.transpose() * Je;
        // Cross block in the lower triangle.
        if (eo > co) {
          A.block<6, 6>(eo, co).noalias() += Je.transpose() * Jc;
        } else {
          A.block<6, 6>(co, eo).noalias() += Jc.transpose() * Je;
        }
        G.middleRows<6>(6 * scratch.local_ext[a]).noalias() += Je.transpose() * Jf;
        b.segment<6>(eo).noalias() += Je.transpose() * r_perp.segment<2>(2 * a);
      }
    }
    // F M^-1 F^T = (F L^-T)(F L^-T)^T with M = L L^T: the column block F L^-T of this feature
    // goes into F_all and all features are subtracted at once below (one rank-3n update).
    const Eigen::Matrix3d L_invT = mllt.matrixU().solve(Eigen::Matrix3d::Identity());
    auto F_f = F_all.middleCols<3>(3 * (out.features_used - 1));
    F_f.setZero();
    for (int i = 0; i < nb; ++i) {
      F_f.middleRows<6>(scratch.block_col[i]).noalias() = G.middleRows<6>(6 * i) * L_invT;
    }
  }
  if (!use_qr && out.features_used > 0) {
    A.selfadjointView<Eigen::Lower>().rankUpdate(F_all.leftCols(3 * out.features_used), -1.0);
  }

  Eigen::MatrixXd H_c;
  if (use_qr) {
    H_stack.conservativeResize(rows, K);
    r_stack.conservativeResize(rows);
    compress_qr(&H_stack, &r_stack);
    H_c = std::move(H_stack);
    out.r = std::move(r_stack);
  } else if (out.features_used > 0) {
    const Eigen::MatrixXd A_full = A.selfadjointView<Eigen::Lower>();
    factor_normal_equations(A_full, b, &H_c, &out.r);
  } else {
    H_c.resize(0, K);
    out.r.resize(0);
  }

  out.H = Eigen::MatrixXd::Zero(H_c.rows(), n);
  for (std::size_t blk = 0; blk < layout.block_cov.size(); ++blk) {
    out.H.middleCols(layout.block_cov[blk], 6) = H_c.middleCols(6 * blk, 6);
  }
  return out;
}

}  // namespace vid::msckf
