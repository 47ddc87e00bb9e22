/// @file inertial_alignment.cpp
/// @brief Stereo-inertial alignment of a window (inertial_alignment.h).
#include "vio_core/inertial_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/so3.h"

namespace vid::align {
namespace {

ImuRow lerp(const ImuRow& a, const ImuRow& b, TimeNs t) {
  const double w = b.t == a.t ? 1.0 : static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  return {t, (1.0 - w) * a.gyro + w * b.gyro, (1.0 - w) * a.accel + w * b.accel};
}

}  // namespace

double detail::reprojection_system(const std::vector<Track>& tracks, const std::vector<Eigen::Matrix3d>& R_Kk,
                                   const std::vector<Eigen::Isometry3d>& T_IC, double sigma_norm,
                                   const std::vector<Eigen::Matrix3d>& J_bg,
                                   const std::vector<std::vector<bool>>& keep, const Eigen::VectorXd& x,
                                   Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  const int K = static_cast<int>(R_Kk.size()) - 1;
  const bool with_bg = !J_bg.empty();
  const int ib = 3 * K + 3 * static_cast<int>(tracks.size());
  if (H) {
    H->setZero(x.size(), x.size());
    g->setZero(x.size());
  }
  double cost = 0.0;
  for (std::size_t j = 0; j < tracks.size(); ++j) {
    const Eigen::Vector3d L = x.segment<3>(3 * K + 3 * static_cast<int>(j));
    for (std::size_t o = 0; o < tracks[j].obs.size(); ++o) {
      if (!keep[j][o]) continue;
      const Bearing& br = tracks[j].obs[o];
      const Eigen::Matrix3d R_k =
          with_bg ? Eigen::Matrix3d(R_Kk[br.frame] * so3::exp(J_bg[br.frame] * x.segment<3>(ib))) : R_Kk[br.frame];
      const Eigen::Vector3d p = br.frame < K ? Eigen::Vector3d(x.segment<3>(3 * br.frame)) : Eigen::Vector3d::Zero();
      const Eigen::Vector3d X_I = R_k.transpose() * (L - p);
      const Eigen::Matrix3d R_CI = T_IC[br.cam].linear().transpose();
      const Eigen::Vector3d X_C = R_CI * (X_I - T_IC[br.cam].translation());
      if (X_C.z() < 1e-3) return std::numeric_limits<double>::infinity();
      const double iz = 1.0 / X_C.z();
      const Eigen::Vector2d r = (X_C.head<2>() * iz - br.xy) / sigma_norm;
      cost += r.squaredNorm();
      if (!H) continue;
      Eigen::Matrix<double, 2, 3> J_pi;
      J_pi << iz, 0.0, -X_C.x() * iz * iz, 0.0, iz, -X_C.y() * iz * iz;
      J_pi /= sigma_norm;
      const Eigen::Matrix<double, 2, 3> JL = J_pi * R_CI * R_k.transpose();  // d r / d L; d r / d p = -JL
      const int iL = 3 * K + 3 * static_cast<int>(j), ip = 3 * br.frame;
      H->block<3, 3>(iL, iL) += JL.transpose() * JL;
      g->segment<3>(iL) += JL.transpose() * r;
      if (br.frame < K) {
        H->block<3, 3>(ip, ip) += JL.transpose() * JL;
        H->block<3, 3>(iL, ip) -= JL.transpose() * JL;
        H->block<3, 3>(ip, iL) -= JL.transpose() * JL;
        g->segment<3>(ip) -= JL.transpose() * r;
      }
      if (with_bg) {  // X_I(d + e) = X_I + [X_I]x J_k e
        const Eigen::Matrix<double, 2, 3> JB = J_pi * R_CI * so3::skew(X_I) * J_bg[br.frame];
        H->block<3, 3>(ib, ib) += JB.transpose() * JB;
        H->block<3, 3>(ib, iL) += JB.transpose() * JL;
        H->block<3, 3>(iL, ib) += JL.transpose() * JB;
        if (br.frame < K) {
          H->block<3, 3>(ib, ip) -= JB.transpose() * JL;
          H->block<3, 3>(ip, ib) -= JL.transpose() * JB;
        }
        g->segment<3>(ib) += JB.transpose() * r;
      }
    }
  }
  return cost;
}

namespace {
using detail::reprojection_system;

/// Levenberg-Marquardt on the reprojection errors from the linear solution @p x: the linear
/// system's depth-weighted algebraic error is biased at low disparity (rope_snap's stereo
/// positions read 3-15 % short with 0.5 px of bearing noise, docs/notes/initialization.md);
/// the reprojection error is the bearings' likelihood. On return @p H is the Gauss-Newton
/// normal matrix at @p x and the result the cost; the input is kept when no step lowers it.
double refine_reprojection(const std::vector<Track>& tracks, const std::vector<Eigen::Matrix3d>& R_Kk,
                           const std::vector<Eigen::Isometry3d>& T_IC, double sigma_norm,
                           const std::vector<Eigen::Matrix3d>& J_bg, const std::vector<std::vector<bool>>& keep,
                           Eigen::VectorXd* x, Eigen::MatrixXd* H) {
  Eigen::VectorXd g;
  double cost = reprojection_system(tracks, R_Kk, T_IC, sigma_norm, J_bg, keep, *x, H, &g);
  if (!std::isfinite(cost)) return cost;
  double lambda = 1e-6 * H->diagonal().maxCoeff();
  for (int it = 0; it < 10; ++it) {
    Eigen::MatrixXd Hd = *H;
    Hd.diagonal().array() += lambda;
    const Eigen::VectorXd step = Hd.ldlt().solve(-g);
    const Eigen::VectorXd x_new = *x + step;
    const double c_new = reprojection_system(tracks, R_Kk, T_IC, sigma_norm, J_bg, keep, x_new, nullptr, nullptr);
    if (!(c_new < cost)) {
      lambda *= 10.0;
      continue;
    }
    const bool converged = cost - c_new < 1e-6 * cost;
    *x = x_new;
    lambda = std::max(lambda * 0.1, 1e-12);
    cost = reprojection_system(tracks, R_Kk, T_IC, sigma_norm, J_bg, keep, *x, H, &g);
    if (converged) break;
  }
  return cost;
}

}  // namespace

WindowIntegrals integrate_window(const std::vector<ImuRow>& imu, const std::vector<TimeNs>& frame_times) {
  // Grid: the frame times and the samples between them; inputs interpolated at the frames.
  std::vector<ImuRow> grid;
  std::size_t j = 0;
  for (TimeNs tf : frame_times) {
    while (j < imu.size() && imu[j].t < tf) {
      if (imu[j].t > frame_times.front()) grid.push_back(imu[j]);
      ++j;
    }
    const std::size_t hi = std::min(j, imu.size() - 1), lo = hi > 0 ? hi - 1 : 0;
    grid.push_back(lerp(imu[lo], imu[hi], tf));
  }
  // Integrals in I_0 (the first frame's IMU frame), recorded at the frames.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity(), Rv = Eigen::Matrix3d::Zero(), Rp = Eigen::Matrix3d::Zero();
  Eigen::Vector3d V = Eigen::Vector3d::Zero(), P = Eigen::Vector3d::Zero();
  std::vector<Eigen::Matrix3d> R0k, RV, RP;
  std::vector<Eigen::Vector3d> V0, P0;
  std::size_t f = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (i > 0) {
      const double dt = ns_to_s(grid[i].t - grid[i - 1].t);
      const Eigen::Matrix3d R1 = R * so3::exp(0.5 * (grid[i - 1].gyro + grid[i].gyro) * dt);
      const Eigen::Vector3d A = 0.5 * (R * grid[i - 1].accel + R1 * grid[i].accel);
      const Eigen::Matrix3d Rm = 0.5 * (R + R1);
      P += V * dt + 0.5 * A * dt * dt;
      V += A * dt;
      Rp += Rv * dt + 0.5 * Rm * dt * dt;
      Rv += Rm * dt;
      R = so3::orthonormalized(R1);
    }
    if (f < frame_times.size() && grid[i].t == frame_times[f]) {
      R0k.push_back(R);
      V0.push_back(V);
      P0.push_back(P);
      RV.push_back(Rv);
      RP.push_back(Rp);
      ++f;
    }
  }
  // To I_K: alpha_k = P(t_k) - P(t_K) - V(t_K) tau_k (the integrals' origin cancels).
  WindowIntegrals w;
  const std::size_t K = R0k.size() - 1;
  const Eigen::Matrix3d R_K0 = R0k[K].transpose();
  for (std::size_t k = 0; k <= K; ++k) {
    const double tau = ns_to_s(frame_times[k] - frame_times[K]);
    w.tau.push_back(tau);
    w.R_Kk.push_back(R_K0 * R0k[k]);
    w.alpha.push_back(R_K0 * (P0[k] - P0[K] - V0[K] * tau));
    w.C.push_back(R_K0 * (RP[k] - RP[K] - RV[K] * tau));
  }
  return w;
}

std::optional<FramePositions> solve_frame_positions(const std::vector<Track>& tracks,
                                                    const std::vector<Eigen::Matrix3d>& R_Kk,
                                                    const std::vector<Eigen::Isometry3d>& T_IC, double sigma_norm,
                                                    std::string* why, const std::vector<Eigen::Matrix3d>& J_bg) {
  const int K = static_cast<int>(R_Kk.size()) - 1;  // frames 0..K-1 have unknown positions
  const int J = static_cast<int>(tracks.size());
  const bool with_bg = !J_bg.empty();
  const int ib = 3 * K + 3 * J;  // the gyro-bias correction's columns (with_bg)
  const int n = ib + (with_bg ? 3 : 0);
  std::vector<std::vector<Eigen::Vector3d>> X_prev(J);  // X_I of each bearing, previous pass
  std::vector<std::vector<double>> depth(J);  // per bearing, from the previous pass
  std::vector<std::vector<bool>> keep(J);
  for (int j = 0; j < J; ++j) {
    depth[j].assign(tracks[j].obs.size(), 1.0);
    keep[j].assign(tracks[j].obs.size(), true);
    X_prev[j].assign(tracks[j].obs.size(), Eigen::Vector3d::Zero());
  }
  Eigen::VectorXd x;
  Eigen::MatrixXd H;
  double chi2 = 0.0;
  int nobs = 0;
  for (int pass = 0; pass < 3; ++pass) {
    H.setZero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    nobs = 0;
    for (int j = 0; j < J; ++j) {
      for (std::size_t o = 0; o < tracks[j].obs.size(); ++o) {
        if (!keep[j][o]) continue;
        const Bearing& br = tracks[j].obs[o];
        Eigen::Matrix<double, 2, 3> M;
        M << 1, 0, -br.xy.x(), 0, 1, -br.xy.y();
        const Eigen::Matrix3d R_CI = T_IC[br.cam].linear().transpose();
        const double wgt = 1.0 / (sigma_norm * depth[j][o]);
        const Eigen::Matrix<double, 2, 3> JL = wgt * M * R_CI * R_Kk[br.frame].transpose();
        const Eigen::Vector2d rhs = wgt * M * R_CI * T_IC[br.cam].translation();
        const int iL = 3 * K + 3 * j, ip = 3 * br.frame;
        H.block<3, 3>(iL, iL) += JL.transpose() * JL;
        b.segment<3>(iL) += JL.transpose() * rhs;
        if (br.frame < K) {  // J_p = -J_L
          H.block<3, 3>(ip, ip) += JL.transpose() * JL;
          H.block<3, 3>(iL, ip) -= JL.transpose() * JL;
          H.block<3, 3>(ip, iL) -= JL.transpose() * JL;
          b.segment<3>(ip) -= JL.transpose() * rhs;
        }
        if (with_bg && pass > 0) {
          // R_Kk(b + d) = R_Kk Exp(J_k d): X_I gains [X_I]x J_k d (X_I of the previous pass).
          const Eigen::Matrix<double, 2, 3> JB = wgt * M * R_CI * so3::skew(X_prev[j][o]) * J_bg[br.frame];
          H.block<3, 3>(ib, ib) += JB.transpose() * JB;
          H.block<3, 3>(ib, iL) += JB.transpose() * JL;
          H.block<3, 3>(iL, ib) += JL.transpose() * JB;
          if (br.frame < K) {
            H.block<3, 3>(ib, ip) -= JB.transpose() * JL;
            H.block<3, 3>(ip, ib) -= JL.transpose() * JB;
          }
          b.segment<3>(ib) += JB.transpose() * rhs;
        }
        ++nobs;
      }
    }
    if (with_bg && pass == 0)  // no bias column yet
      H.block<3, 3>(ib, ib) = Eigen::Matrix3d::Identity() * H.diagonal().head(ib).maxCoeff();
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        ldlt.vectorD().minCoeff() <= 1e-12 * ldlt.vectorD().maxCoeff()) {
      if (why) *why = "stereo positions not determined (too few or degenerate features)";
      return std::nullopt;
    }
    x = ldlt.solve(b);
    // Depths and normalized residuals for the next pass; outliers beyond 4 sigma of the noise,
    // or of the residuals' own scale where that is larger (rotations still off by a gyro bias).
    const double outlier_r2 = 16.0 * std::max(1.0, chi2 / std::max(1, nobs) / 2.0);
    chi2 = 0.0;
    for (int j = 0; j < J; ++j) {
      const Eigen::Vector3d L = x.segment<3>(3 * K + 3 * j);
      for (std::size_t o = 0; o < tracks[j].obs.size(); ++o) {
        const Bearing& br = tracks[j].obs[o];
        const Eigen::Vector3d p = br.frame < K ? Eigen::Vector3d(x.segment<3>(3 * br.frame)) : Eigen::Vector3d::Zero();
        Eigen::Vector3d X_I = R_Kk[br.frame].transpose() * (L - p);
        if (with_bg && pass > 0) X_I += so3::skew(X_prev[j][o]) * J_bg[br.frame] * x.segment<3>(ib);
        const Eigen::Vector3d X_C = T_IC[br.cam].inverse() * X_I;
        X_prev[j][o] = X_I;
        const double r2 = ((X_C.head<2>() / X_C.z() - br.xy) / sigma_norm).squaredNorm();
        if (!keep[j][o]) continue;
        chi2 += r2;
        depth[j][o] = std::max(X_C.z(), 0.1);
        if (pass == 1 && (X_C.z() < 0.1 || r2 > outlier_r2)) keep[j][o] = false;
      }
    }
  }
  // The linear passes give the start and the outliers; the reprojection error the estimate.
  Eigen::VectorXd x_refined = x;
  Eigen::MatrixXd H_refined;
  const double c = refine_reprojection(tracks, R_Kk, T_IC, sigma_norm, J_bg, keep, &x_refined, &H_refined);
  if (std::isfinite(c)) {
    x = x_refined;
    H = H_refined;
    chi2 = c;
  }
  const int dof = 2 * nobs - n;
  if (dof <= 0) {
    if (why) *why = "too few bearings for the stereo positions";
    return std::nullopt;
  }
  FramePositions out;
  out.chi2_per_dof = chi2 / dof;
  out.landmarks = J;
  out.observations = nobs;
  for (int k = 0; k < K; ++k) out.p.push_back(x.segment<3>(3 * k));
  out.p.push_back(Eigen::Vector3d::Zero());
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, 3 * K);
  E.topRows(3 * K).setIdentity();
  out.cov = Eigen::LDLT<Eigen::MatrixXd>(H).solve(E).topRows(3 * K) * std::max(1.0, out.chi2_per_dof);
  out.cov = 0.5 * (out.cov + out.cov.transpose()).eval();
  if (with_bg) {
    out.d_bg = x.segment<3>(ib);
    Eigen::MatrixXd Eb = Eigen::MatrixXd::Zero(n, 3);
    Eb.bottomRows(3).setIdentity();
    out.cov_bg = Eigen::LDLT<Eigen::MatrixXd>(H).solve(Eb).bottomRows(3) * std::max(1.0, out.chi2_per_dof);
  }
  return out;
}

Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& d) {
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = d.unitOrthogonal();
  B.col(1) = d.cross(B.col(0));
  return B;
}

Eigen::Matrix<double, 9, 8> tangent_map(const Eigen::Vector3d& d, double gravity) {
  Eigen::Matrix<double, 9, 8> T = Eigen::Matrix<double, 9, 8>::Zero();
  T.block<3, 3>(0, 0).setIdentity();
  T.block<3, 2>(3, 3) = gravity * tangent_basis(d);
  T.block<3, 3>(6, 5).setIdentity();
  return T;
}

double alpha_covariance(double a, double b) {
  const double m = std::max(a, b);  // both <= 0
  return -(m * m * m / 3.0 - (a + b) * m * m / 2.0 + a * b * m);
}

AlignedState solve_gravity_velocity(const FramePositions& pos, const WindowIntegrals& w, double accel_density,
                                    double sigma_ba, double gravity, const Eigen::MatrixXd& alpha_cov_extra) {
  const int K = static_cast<int>(w.tau.size()) - 1;
  // 3K x 3K: visual + accelerometer noise of alpha. The positions' covariance is the
  // reprojection refinement's as it is: over Monte-Carlo draws (tests/vio_core/test_dynamic_init.cpp)
  // the velocity NEES per dof is 0.83 with it (the linear solve alone needed it doubled: its
  // algebraic error biased the weak-baseline scale).
  Eigen::MatrixXd S = pos.cov;
  if (alpha_cov_extra.rows() == S.rows()) S += alpha_cov_extra;
  Eigen::VectorXd z(3 * K);
  for (int i = 0; i < K; ++i) {
    z.segment<3>(3 * i) = pos.p[i] - w.alpha[i];
    for (int k = 0; k < K; ++k)
      S.block<3, 3>(3 * i, 3 * k).diagonal().array() +=
          accel_density * accel_density * alpha_covariance(w.tau[i], w.tau[k]);
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  // Unknowns (v, g, b_a) with g = gravity * d, d a unit direction refined on its tangent plane.
  Eigen::MatrixXd A(3 * K, 9);
  for (int i = 0; i < K; ++i) {
    A.block<3, 3>(3 * i, 0) = w.tau[i] * Eigen::Matrix3d::Identity();
    A.block<3, 3>(3 * i, 3) = 0.5 * w.tau[i] * w.tau[i] * Eigen::Matrix3d::Identity();
    A.block<3, 3>(3 * i, 6) = -w.C[i];
  }
  const Eigen::MatrixXd WA = llt.solve(A);
  const Eigen::VectorXd Wz = llt.solve(z);
  Eigen::Matrix<double, 9, 9> N = A.transpose() * WA;
  N.block<3, 3>(6, 6) += Eigen::Matrix3d::Identity() / (sigma_ba * sigma_ba);
  Eigen::Matrix<double, 9, 1> y = N.ldlt().solve(A.transpose() * Wz);
  Eigen::Vector3d d = y.segment<3>(3).normalized();
  // Tangent refinement: g = gravity (d + B delta), linear in (v, delta, b_a).
  Eigen::Matrix<double, 9, 8> T;  // (v, g, b_a) = T (v, delta, b_a) about d
  Eigen::Matrix<double, 8, 8> cov8;
  Eigen::Matrix<double, 8, 1> u;
  double chi2 = 0.0;
  for (int it = 0; it < 5; ++it) {
    const Eigen::Matrix<double, 3, 2> B = tangent_basis(d);
    T = tangent_map(d, gravity);
    const Eigen::MatrixXd A8 = A * T;
    const Eigen::VectorXd z8 = z - A.middleCols<3>(3) * (gravity * d);
    Eigen::Matrix<double, 8, 8> N8 = A8.transpose() * llt.solve(A8);
    N8.block<3, 3>(5, 5) += Eigen::Matrix3d::Identity() / (sigma_ba * sigma_ba);
    u = N8.ldlt().solve(A8.transpose() * llt.solve(z8));
    cov8 = N8.inverse();
    const Eigen::VectorXd r = z8 - A8 * u;
    chi2 = r.dot(llt.solve(r)) + u.tail<3>().squaredNorm() / (sigma_ba * sigma_ba);
    d = (d + B * u.segment<2>(3)).normalized();
  }
  AlignedState s;
  s.v_I = u.head<3>();
  s.g_I = gravity * d;
  s.b_a = u.tail<3>();
  s.chi2_per_dof = chi2 / std::max(1, 3 * K - 8);
  s.cov = T * cov8 * T.transpose() * std::max(1.0, s.chi2_per_dof);
  return s;
}

}  // namespace vid::align
