/// @file mono_alignment.cpp
/// @brief Mono visual-inertial alignment of a window (mono_alignment.h).
#include "vio_core/mono_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/so3.h"

namespace vid::align {
namespace {

/// d p_k / d (v, g, b_a) of frame k < K (p_k = v tau + g tau^2 / 2 + alpha_k - C_k b_a).
Eigen::Matrix<double, 3, 9> position_map(const WindowIntegrals& w, int k) {
  Eigen::Matrix<double, 3, 9> A;
  A << w.tau[k] * Eigen::Matrix3d::Identity(), 0.5 * w.tau[k] * w.tau[k] * Eigen::Matrix3d::Identity(), -w.C[k];
  return A;
}

/// argmin y^T H y - 2 b^T y subject to |y_g| = G, y_g = y.segment<3>(3): the rest eliminated,
/// the 3 x 3 problem (A - lambda I) g = c with lambda below A's smallest eigenvalue is the
/// global minimum on the sphere (the trust-region boundary condition); lambda by bisection on
/// the monotone |g(lambda)|. nullopt when the rest is singular.
std::optional<Eigen::VectorXd> solve_on_sphere(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, double G) {
  const int n = static_cast<int>(H.rows());
  std::vector<int> rest;
  for (int i = 0; i < n; ++i)
    if (i < 3 || i >= 6) rest.push_back(i);
  const Eigen::MatrixXd H_rr = H(rest, rest), H_rg = H(rest, Eigen::seqN(3, 3));
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H_rr);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
      ldlt.vectorD().minCoeff() <= 1e-12 * ldlt.vectorD().maxCoeff())
    return std::nullopt;
  const Eigen::MatrixXd X = ldlt.solve(H_rg);
  const Eigen::VectorXd x_b = ldlt.solve(Eigen::VectorXd(b(rest)));
  const Eigen::Matrix3d A = H.block<3, 3>(3, 3) - H_rg.transpose() * X;
  const Eigen::Vector3d c = b.segment<3>(3) - H_rg.transpose() * x_b;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (A + A.transpose()));
  const Eigen::Vector3d q = eig.eigenvectors().transpose() * c;
  const Eigen::Vector3d a = eig.eigenvalues();
  const auto norm_at = [&](double lambda) { return (q.array() / (a.array() - lambda)).matrix().norm(); };
  double hi = a[0] - 1e-12 * std::max(1.0, std::abs(a[0])), step = std::max(1.0, std::abs(a[0]));
  double lo = hi - step;
  while (norm_at(lo) > G && step < 1e30) lo = hi - (step *= 10.0);
  for (int it = 0; it < 200 && hi - lo > 1e-14 * std::max(1.0, std::abs(lo)); ++it) {
    const double mid = 0.5 * (lo + hi);
    (norm_at(mid) > G ? hi : lo) = mid;
  }
  const double lambda = 0.5 * (lo + hi);
  const Eigen::Vector3d g = eig.eigenvectors() * (q.array() / (a.array() - lambda)).matrix();
  Eigen::VectorXd y(n);
  y.segment<3>(3) = G * g.normalized();
  y(rest) = x_b - X * y.segment<3>(3);
  return y;
}

/// Step 1 of mono_alignment.h. (a) Structure up to scale: the camera centres c_k (in I_K's axes,
/// relative to the last frame's centre) and the landmarks from the bearings' homogeneous rows
/// M R_CI R_Kk^T (L - c_k) = 0 with the rotations held: the null vector by inverse iteration,
/// its sign the one that puts most points in front of the camera; depth-weighted and re-solved
/// twice, outliers past 4 sigma dropped. (b) Scale s, v, g with |g| = G from
/// s c_k + (I - R_Kk) p_IC = v tau_k + g tau_k^2 / 2 + alpha_k, weighted by the alphas'
/// accelerometer noise, b_a held at 0 (over a short window it trades with g and the scale; the
/// Levenberg-Marquardt step estimates it). Returns (v, g, b_a = 0, L_0..L_{J-1}) in I_K and the
/// bearings kept; nullopt when the structure or a positive scale is not determined.
std::optional<Eigen::VectorXd> linear_start(const std::vector<Track>& tracks, const WindowIntegrals& w_in,
                                            const Eigen::Isometry3d& T_IC, const MonoNoise& noise,
                                            const std::vector<Eigen::Matrix3d>& J_bg,
                                            const Eigen::MatrixXd& J_alpha_bg, std::vector<std::vector<bool>>* keep,
                                            Eigen::Vector3d* d_bg) {
  // The rotations and alphas at the bias correction found so far (alternation below).
  WindowIntegrals w = w_in;
  d_bg->setZero();
  const int K = static_cast<int>(w.tau.size()) - 1;
  const int J = static_cast<int>(tracks.size());
  const int n = 3 * K + 3 * J;  // (c_0..c_{K-1}, L_0..L_{J-1})
  const Eigen::Matrix3d R_CI = T_IC.linear().transpose();
  std::vector<std::vector<double>> depth(J);
  keep->assign(J, {});
  for (int j = 0; j < J; ++j) {
    depth[j].assign(tracks[j].obs.size(), 1.0);
    (*keep)[j].assign(tracks[j].obs.size(), true);
  }
  const auto point_in_camera = [&](const Eigen::VectorXd& x, int j, int k) -> Eigen::Vector3d {
    const Eigen::Vector3d c = k < K ? Eigen::Vector3d(x.segment<3>(3 * k)) : Eigen::Vector3d::Zero();
    return R_CI * w.R_Kk[k].transpose() * (x.segment<3>(3 * K + 3 * j) - c);
  };
  Eigen::VectorXd x = Eigen::VectorXd::Ones(n).normalized();
  double chi2 = 0.0;
  int nobs = 0;
  // A gyro bias bends the held rotations, and bent rotations bend the structure (a 0.05 rad/s
  // bias over 2 s is 6 degrees: enough to flip the scale's sign). So the structure passes
  // alternate with a gyro-bias step on the same algebraic rows, linear in the bias at fixed
  // structure: the rows' Jacobian M R_CI [X_I]x J_bg,k (X_I = R_Kk^T (L - c_k)).
  const int passes = J_bg.empty() ? 3 : 8;
  for (int pass = 0; pass < passes; ++pass) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    nobs = 0;
    for (int j = 0; j < J; ++j) {
      const int iL = 3 * K + 3 * j;
      for (std::size_t o = 0; o < tracks[j].obs.size(); ++o) {
        if (!(*keep)[j][o]) continue;
        const Bearing& br = tracks[j].obs[o];
        Eigen::Matrix<double, 2, 3> M;
        M << 1, 0, -br.xy.x(), 0, 1, -br.xy.y();
        const Eigen::Matrix<double, 2, 3> JL =
            M * R_CI * w.R_Kk[br.frame].transpose() / (noise.sigma_norm * depth[j][o]);
        const Eigen::Matrix3d JtJ = JL.transpose() * JL;
        H.block<3, 3>(iL, iL) += JtJ;
        if (br.frame < K) {  // d / d c_k = -J_L
          const int ic = 3 * br.frame;
          H.block<3, 3>(ic, ic) += JtJ;
          H.block<3, 3>(ic, iL) -= JtJ;
          H.block<3, 3>(iL, ic) -= JtJ;
        }
        ++nobs;
      }
      // A landmark left with fewer than three bearings says little and may say nothing: out
      // (solve_mono_window drops it), held at 0 so that the system has only the scale free.
      if (std::count((*keep)[j].begin(), (*keep)[j].end(), true) >= 3) continue;
      std::fill((*keep)[j].begin(), (*keep)[j].end(), false);
      H.block<3, 3>(iL, iL) = Eigen::Matrix3d::Identity() * std::max(1.0, H.diagonal().maxCoeff());
    }
    // The scale is H's exact null direction: inverse iteration with a tiny shift.
    const double mu = 1e-10 * H.diagonal().maxCoeff();
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(H + mu * Eigen::MatrixXd::Identity(n, n));
    if (ldlt.info() != Eigen::Success) return std::nullopt;
    for (int it = 0; it < 8; ++it) x = ldlt.solve(x).normalized();
    if (!x.allFinite()) return std::nullopt;
    int in_front = 0, behind = 0;
    for (int j = 0; j < J; ++j)
      for (std::size_t o = 0; o < tracks[j].obs.size(); ++o)
        if ((*keep)[j][o]) (point_in_camera(x, j, tracks[j].obs[o].frame).z() > 0 ? in_front : behind)++;
    if (behind > in_front) x = -x;
    // Depths (the structure's scale is arbitrary: relative to the median), outliers at pass 1.
    std::vector<double> z;
    for (int j = 0; j < J; ++j)
      for (std::size_t o = 0; o < tracks[j].obs.size(); ++o)
        if ((*keep)[j][o]) z.push_back(point_in_camera(x, j, tracks[j].obs[o].frame).z());
    if (z.empty()) return std::nullopt;
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    const double z_med = z[z.size() / 2];
    if (!(z_med > 0)) return std::nullopt;
    const double outlier_r2 = 16.0 * std::max(1.0, chi2 / std::max(1, nobs) / 2.0);
    chi2 = 0.0;
    for (int j = 0; j < J; ++j) {
      for (std::size_t o = 0; o < tracks[j].obs.size(); ++o) {
        if (!(*keep)[j][o]) continue;
        const Eigen::Vector3d X_C = point_in_camera(x, j, tracks[j].obs[o].frame);
        const double r2 = ((X_C.head<2>() / X_C.z() - tracks[j].obs[o].xy) / noise.sigma_norm).squaredNorm();
        chi2 += r2;
        depth[j][o] = std::max(X_C.z() / z_med, 0.01);
        if (pass == 1 && (r2 > outlier_r2 || X_C.z() < 0.01 * z_med)) (*keep)[j][o] = false;
      }
    }
    if (J_bg.empty() || pass == passes - 1) continue;
    Eigen::Matrix3d Hb = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gb = Eigen::Vector3d::Zero();
    for (int j = 0; j < J; ++j)
      for (std::size_t o = 0; o < tracks[j].obs.size(); ++o) {
        if (!(*keep)[j][o]) continue;
        const Bearing& br = tracks[j].obs[o];
        const Eigen::Vector3d c = br.frame < K ? Eigen::Vector3d(x.segment<3>(3 * br.frame)) : Eigen::Vector3d::Zero();
        const Eigen::Vector3d X_I = w.R_Kk[br.frame].transpose() * (x.segment<3>(3 * K + 3 * j) - c);
        Eigen::Matrix<double, 2, 3> M;
        M << 1, 0, -br.xy.x(), 0, 1, -br.xy.y();
        const double wt = 1.0 / (noise.sigma_norm * depth[j][o] * z_med);
        const Eigen::Vector2d r0 = wt * M * R_CI * X_I;
        const Eigen::Matrix<double, 2, 3> A = wt * M * R_CI * so3::skew(X_I) * J_bg[br.frame];
        Hb += A.transpose() * A;
        gb += A.transpose() * r0;
      }
    const Eigen::Vector3d step = -Hb.ldlt().solve(gb);
    if (!step.allFinite()) break;
    *d_bg += step;
    for (int k = 0; k <= K; ++k) w.R_Kk[k] = w_in.R_Kk[k] * so3::exp(J_bg[k] * *d_bg);
    for (int k = 0; k < K; ++k) w.alpha[k] = w_in.alpha[k] + J_alpha_bg.middleRows<3>(3 * k) * *d_bg;
    if (step.norm() < 1e-5 && pass >= 2) break;
  }
  // (b) (v, g, b_a, s): rows s c_k - v tau - g tau^2 / 2 + C_k b_a = alpha_k - (I - R_Kk) p_IC.
  const Eigen::Vector3d p_IC = T_IC.translation();
  Eigen::MatrixXd A(3 * K, 10);
  Eigen::VectorXd r(3 * K);
  Eigen::MatrixXd S(3 * K, 3 * K);
  for (int i = 0; i < K; ++i) {
    A.block<3, 9>(3 * i, 0) = -position_map(w, i);
    A.block<3, 1>(3 * i, 9) = x.segment<3>(3 * i);
    r.segment<3>(3 * i) = w.alpha[i] - (Eigen::Matrix3d::Identity() - w.R_Kk[i]) * p_IC;
    for (int k = 0; k < K; ++k)
      S.block<3, 3>(3 * i, 3 * k) = alpha_covariance(w.tau[i], w.tau[k]) * Eigen::Matrix3d::Identity();
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  Eigen::MatrixXd N = A.transpose() * llt.solve(A);
  Eigen::VectorXd b = A.transpose() * llt.solve(r);
  N.middleRows<3>(6).setZero();  // b_a held at 0
  N.middleCols<3>(6).setZero();
  N.block<3, 3>(6, 6) = std::max(1.0, N.diagonal().maxCoeff()) * Eigen::Matrix3d::Identity();
  b.segment<3>(6).setZero();
  const std::optional<Eigen::VectorXd> u = solve_on_sphere(N, b, noise.gravity);
  if (!u || !((*u)[9] > 0)) return std::nullopt;
  Eigen::VectorXd y(9 + 3 * J);
  y.head<9>() = u->head<9>();
  for (int j = 0; j < J; ++j) y.segment<3>(9 + 3 * j) = (*u)[9] * x.segment<3>(3 * K + 3 * j) + p_IC;
  return y;
}

}  // namespace

std::optional<MonoAlignment> solve_mono_window(const std::vector<Track>& all_tracks, const WindowIntegrals& w,
                                               const Eigen::Isometry3d& T_IC, const MonoNoise& noise,
                                               const std::vector<Eigen::Matrix3d>& J_bg,
                                               const Eigen::MatrixXd& J_alpha_bg, std::string* why) {
  std::vector<std::vector<bool>> start_keep;
  Eigen::Vector3d d_bg_start = Eigen::Vector3d::Zero();
  const std::optional<Eigen::VectorXd> y =
      linear_start(all_tracks, w, T_IC, noise, J_bg, J_alpha_bg, &start_keep, &d_bg_start);
  if (!y || y->segment<3>(3).norm() < 1e-6) {
    if (why) *why = "mono window not determined (too few features or too little motion)";
    return std::nullopt;
  }
  const int K = static_cast<int>(w.tau.size()) - 1;
  const bool with_bg = !J_bg.empty();
  std::vector<Eigen::Vector3d> p_start(K + 1, Eigen::Vector3d::Zero());
  std::vector<Eigen::Matrix3d> R_start = w.R_Kk;
  for (int k = 0; k < K; ++k) {
    p_start[k] = position_map(w, k) * y->head<9>() + w.alpha[k];
    if (with_bg) p_start[k] += J_alpha_bg.middleRows<3>(3 * k) * d_bg_start;
  }
  if (with_bg)
    for (int k = 0; k <= K; ++k) R_start[k] = w.R_Kk[k] * so3::exp(J_bg[k] * d_bg_start);
  // The landmarks the start kept, with their kept bearings; a landmark the start put behind one
  // of its cameras (a poorly conditioned ray, near the epipole) is left out: the reprojection
  // errors are not defined there.
  const Eigen::Matrix3d R_CI = T_IC.linear().transpose();
  std::vector<Track> tracks;
  std::vector<Eigen::Vector3d> L_start;
  for (std::size_t j = 0; j < all_tracks.size(); ++j) {
    const Eigen::Vector3d L = y->segment<3>(9 + 3 * static_cast<int>(j));
    Track t{all_tracks[j].id, {}};
    bool in_front = true;
    for (std::size_t o = 0; o < all_tracks[j].obs.size(); ++o) {
      if (!start_keep[j][o]) continue;
      const int k = all_tracks[j].obs[o].frame;
      in_front = in_front && (R_CI * (R_start[k].transpose() * (L - p_start[k]) - T_IC.translation())).z() > 1e-3;
      t.obs.push_back(all_tracks[j].obs[o]);
    }
    if (t.obs.empty() || !in_front) continue;
    tracks.push_back(std::move(t));
    L_start.push_back(L);
  }
  std::vector<std::vector<bool>> keep;
  for (const Track& t : tracks) keep.emplace_back(t.obs.size(), true);
  const int J = static_cast<int>(tracks.size());
  const int ib = 3 * K + 3 * J;
  const int n = ib + (with_bg ? 3 : 0);  // reprojection_system's unknowns (p, L, d_bg)
  const int N = n + 8;                   // and (v, delta, b_a), g = gravity (d + B delta)
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < K; ++k) x.segment<3>(3 * k) = p_start[k];
  if (with_bg) x.segment<3>(ib) = d_bg_start;
  for (int j = 0; j < J; ++j) x.segment<3>(3 * K + 3 * j) = L_start[j];
  Eigen::Vector3d v = y->head<3>(), d = y->segment<3>(3).normalized(), b_a = y->segment<3>(6);

  // The alphas' accelerometer noise (per axis alike), as solve_gravity_velocity's.
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(3 * K, 3 * K);
  for (int i = 0; i < K; ++i)
    for (int k = 0; k < K; ++k)
      S.block<3, 3>(3 * i, 3 * k).diagonal().setConstant(noise.accel_density * noise.accel_density *
                                                         alpha_covariance(w.tau[i], w.tau[k]));
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  const std::vector<Eigen::Isometry3d> cams{T_IC};
  const double prior = 1.0 / (noise.sigma_ba * noise.sigma_ba);

  // The whole cost and, with H, its Gauss-Newton system over (x, v, delta, b_a) at delta = 0.
  const auto system = [&](const Eigen::VectorXd& xs, const Eigen::Vector3d& vs, const Eigen::Vector3d& ds,
                          const Eigen::Vector3d& bs, Eigen::MatrixXd* H, Eigen::VectorXd* g, double* c_in) {
    Eigen::MatrixXd Hv;
    Eigen::VectorXd gv;
    const double c_vis = detail::reprojection_system(tracks, w.R_Kk, cams, noise.sigma_norm, J_bg, keep, xs,
                                                     H ? &Hv : nullptr, H ? &gv : nullptr);
    const Eigen::Matrix<double, 3, 2> B = tangent_basis(ds);
    Eigen::VectorXd e(3 * K);
    Eigen::MatrixXd Je = Eigen::MatrixXd::Zero(3 * K, N);
    for (int k = 0; k < K; ++k) {
      const Eigen::Matrix<double, 3, 9> A = position_map(w, k);
      e.segment<3>(3 * k) = xs.segment<3>(3 * k) - w.alpha[k] - A.leftCols<3>() * vs -
                            A.middleCols<3>(3) * (noise.gravity * ds) - A.rightCols<3>() * bs;
      Je.block<3, 3>(3 * k, 3 * k).setIdentity();
      Je.block<3, 3>(3 * k, n) = -A.leftCols<3>();
      Je.block<3, 2>(3 * k, n + 3) = -A.middleCols<3>(3) * noise.gravity * B;
      Je.block<3, 3>(3 * k, n + 5) = -A.rightCols<3>();
      if (with_bg) {
        e.segment<3>(3 * k) -= J_alpha_bg.middleRows<3>(3 * k) * xs.segment<3>(ib);
        Je.block<3, 3>(3 * k, ib) = -J_alpha_bg.middleRows<3>(3 * k);
      }
    }
    const Eigen::VectorXd We = llt.solve(e);
    *c_in = e.dot(We);
    if (H) {
      const Eigen::MatrixXd WJ = llt.solve(Je);
      *H = Je.transpose() * WJ;
      H->topLeftCorner(n, n) += Hv;
      H->block<3, 3>(n + 5, n + 5) += prior * Eigen::Matrix3d::Identity();
      *g = Je.transpose() * We;
      g->head(n) += gv;
      g->segment<3>(n + 5) += prior * bs;
    }
    return c_vis + *c_in + prior * bs.squaredNorm();
  };

  // Levenberg-Marquardt from the linear start.
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  double c_in = 0.0;
  double cost = system(x, v, d, b_a, &H, &g, &c_in);
  if (!std::isfinite(cost)) {
    if (why) *why = "mono window: a landmark behind its camera at the start";
    return std::nullopt;
  }
  double lambda = 1e-6 * H.diagonal().maxCoeff();
  for (int it = 0; it < 20; ++it) {
    Eigen::MatrixXd Hd = H;
    Hd.diagonal().array() += lambda;
    const Eigen::VectorXd step = Hd.ldlt().solve(-g);
    const Eigen::VectorXd x_new = x + step.head(n);
    const Eigen::Vector3d v_new = v + step.segment<3>(n);
    const Eigen::Vector3d d_new = (d + tangent_basis(d) * step.segment<2>(n + 3)).normalized();
    const Eigen::Vector3d b_new = b_a + step.segment<3>(n + 5);
    double c_in_new = 0.0;
    const double c_new = system(x_new, v_new, d_new, b_new, nullptr, nullptr, &c_in_new);
    if (!(c_new < cost)) {
      lambda *= 10.0;
      if (lambda > 1e12 * H.diagonal().maxCoeff()) break;
      continue;
    }
    const bool converged = cost - c_new < 1e-8 * cost;
    x = x_new, v = v_new, d = d_new, b_a = b_new;
    lambda = std::max(lambda * 0.1, 1e-12);
    cost = system(x, v, d, b_a, &H, &g, &c_in);
    if (converged) break;
  }

  int nobs = 0;
  for (const auto& kj : keep) nobs += static_cast<int>(std::count(kj.begin(), kj.end(), true));
  const int dof = 2 * nobs + 3 * K + 3 - N;
  if (dof <= 0) {
    if (why) *why = "too few bearings for the mono window";
    return std::nullopt;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
    if (why) *why = "mono window not determined at the solution";
    return std::nullopt;
  }
  MonoAlignment m;
  m.state.chi2_per_dof = cost / dof;
  const double inflate = std::max(1.0, m.state.chi2_per_dof);
  // Columns wanted of H^-1: the positions, the gyro bias, and (v, delta, b_a).
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(N, 3 * K + 11);
  E.topLeftCorner(3 * K, 3 * K).setIdentity();
  if (with_bg) E.block<3, 3>(ib, 3 * K).setIdentity();
  E.bottomRightCorner<8, 8>().setIdentity();
  const Eigen::MatrixXd Hinv = ldlt.solve(E) * inflate;
  const Eigen::Matrix<double, 8, 8> cov8 = Hinv.bottomRightCorner<8, 8>();
  const Eigen::Matrix<double, 9, 8> T = tangent_map(d, noise.gravity);
  m.state.v_I = v;
  m.state.g_I = noise.gravity * d;
  m.state.b_a = b_a;
  m.state.cov = T * cov8 * T.transpose();
  m.inertial_chi2_per_dof = c_in / std::max(1, 3 * K);
  m.pos.landmarks = J;
  m.pos.observations = nobs;
  m.pos.chi2_per_dof = (cost - c_in - prior * b_a.squaredNorm()) / std::max(1, 2 * nobs - 3 * J - 3 * K);
  for (int k = 0; k < K; ++k) m.pos.p.push_back(x.segment<3>(3 * k));
  m.pos.p.push_back(Eigen::Vector3d::Zero());
  m.pos.cov = Hinv.topLeftCorner(3 * K, 3 * K);
  m.pos.cov = 0.5 * (m.pos.cov + m.pos.cov.transpose()).eval();
  const Eigen::Vector3d p0 = m.pos.p[0];
  m.scale_sigma = p0.norm() > 0 ? std::sqrt(p0.dot(m.pos.cov.topLeftCorner<3, 3>() * p0)) / p0.squaredNorm()
                                : std::numeric_limits<double>::infinity();
  if (with_bg) {
    m.pos.d_bg = x.segment<3>(ib);
    m.pos.cov_bg = Hinv.block<3, 3>(ib, 3 * K);
  }
  return m;
}

}  // namespace vid::align
