/// @file triangulation.cpp
/// @brief Linear midpoint triangulation in the anchor camera frame, refined by
/// Levenberg-damped Gauss-Newton in inverse depth.

#include "vio_core/msckf/triangulation.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace vid::msckf {
namespace {

/// Pose of one observing camera relative to the anchor camera A.
struct RelativePose {
  Eigen::Matrix3d R_CA;
  Eigen::Vector3d p_CA;  ///< position of A's origin in C
  Eigen::Vector3d c_A;   ///< position of C's centre in A
};

/// Inlined kernel of inverse_depth_projection (same math, written out for the hot loop).
inline bool project_inverse_depth(const Eigen::Vector3d& abr, const Eigen::Matrix3d& R_CA,
                                  const Eigen::Vector3d& p_CA, Eigen::Vector2d* z,
                                  Eigen::Matrix<double, 2, 3>* J) {
  // h = rho * p_C = R_CA [alpha, beta, 1] + rho p_CA; z = h.xy / h.z (rho > 0 assumed).
  const Eigen::Vector3d h =
      R_CA.col(0) * abr.x() + R_CA.col(1) * abr.y() + R_CA.col(2) + p_CA * abr.z();
  if (!(h.z() > 1e-12)) return false;
  const double inv_z = 1.0 / h.z();
  *z = h.head<2>() * inv_z;
  if (J != nullptr) {
    // J = dz/dh * [R_CA.col(0), R_CA.col(1), p_CA], dz/dh = inv_z [1 0 -z.x; 0 1 -z.y].
    for (int r = 0; r < 2; ++r) {
      const double zr = (*z)(r);
      (*J)(r, 0) = inv_z * (R_CA(r, 0) - zr * R_CA(2, 0));
      (*J)(r, 1) = inv_z * (R_CA(r, 1) - zr * R_CA(2, 1));
      (*J)(r, 2) = inv_z * (p_CA(r) - zr * p_CA(2));
    }
  }
  return true;
}

double reprojection_cost(const std::vector<CameraRay>& rays,
                         const std::vector<RelativePose>& rel, const Eigen::Vector3d& abr,
                         double* max_err) {
  double cost = 0.0;
  double worst = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Eigen::Vector2d z;
    if (!project_inverse_depth(abr, rel[i].R_CA, rel[i].p_CA, &z, nullptr)) {
      return std::numeric_limits<double>::infinity();
    }
    const double e = (rays[i].uv_norm - z).norm();
    cost += e * e;
    worst = std::max(worst, e);
  }
  if (max_err != nullptr) *max_err = worst;
  return cost;
}

/// Cost and largest error (as reprojection_cost) and Gauss-Newton system H = sum J^T J,
/// g = sum J^T e at abr in one pass; infinite cost (the rest unspecified) if a projection fails.
double cost_and_normal_equations(const std::vector<CameraRay>& rays,
                                 const std::vector<RelativePose>& rel, const Eigen::Vector3d& abr,
                                 Eigen::Matrix3d* H, Eigen::Vector3d* g, double* max_err) {
  double cost = 0.0;
  double worst = 0.0;
  H->setZero();
  g->setZero();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    Eigen::Vector2d z;
    Eigen::Matrix<double, 2, 3> J;
    if (!project_inverse_depth(abr, rel[i].R_CA, rel[i].p_CA, &z, &J)) {
      return std::numeric_limits<double>::infinity();
    }
    const Eigen::Vector2d e = rays[i].uv_norm - z;
    const double e2 = e.squaredNorm();
    cost += e2;
    worst = std::max(worst, e2);  // squared; one sqrt at the end
    H->noalias() += J.transpose() * J;
    g->noalias() += J.transpose() * e;
  }
  *max_err = std::sqrt(worst);
  return cost;
}

}  // namespace

bool inverse_depth_projection(const Eigen::Vector3d& abr, const Eigen::Matrix3d& R_CA,
                              const Eigen::Vector3d& p_CA, Eigen::Vector2d* z,
                              Eigen::Matrix<double, 2, 3>* J) {
  return project_inverse_depth(abr, R_CA, p_CA, z, J);
}

TriangulationResult triangulate(const std::vector<CameraRay>& rays,
                                const TriangulationParams& params) {
  TriangulationResult res;
  if (rays.size() < 2) return res;

  const Eigen::Matrix3d& R_WA = rays[0].R_WC;
  const Eigen::Vector3d& p_WA = rays[0].p_WC;
  std::vector<RelativePose> rel(rays.size());
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  const Eigen::Vector3d d0 = rays[0].uv_norm.homogeneous().normalized();
  double max_parallax = 0.0;
  double max_baseline = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Matrix3d R_AC = R_WA.transpose() * rays[i].R_WC;
    rel[i].c_A = R_WA.transpose() * (rays[i].p_WC - p_WA);
    rel[i].R_CA = R_AC.transpose();
    rel[i].p_CA = -rel[i].R_CA * rel[i].c_A;
    const Eigen::Vector3d v = R_AC * rays[i].uv_norm.homogeneous();
    // Midpoint: minimise the sum of squared distances of p_A to each ray.
    // I - d d^T for the unit ray d = v / |v|, without the square root.
    const Eigen::Matrix3d Pperp =
        Eigen::Matrix3d::Identity() - (v * v.transpose()) * (1.0 / v.squaredNorm());
    A += Pperp;
    b += Pperp * rel[i].c_A;
    if (params.min_parallax_rad > 0.0) {  // only needed for that check
      const Eigen::Vector3d d = v.normalized();
      max_parallax = std::max(max_parallax, std::atan2(d0.cross(d).norm(), d0.dot(d)));
    }
    if (params.min_baseline > 0.0) {  // only needed for that check
      max_baseline = std::max(max_baseline, rel[i].c_A.norm());
    }
  }

  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(A, Eigen::EigenvaluesOnly);
  const double lmin = eig.eigenvalues()(0);
  const double lmax = eig.eigenvalues()(2);
  res.condition = lmin > 0.0 ? lmax / lmin : std::numeric_limits<double>::infinity();
  if (!(res.condition <= params.max_condition)) {
    res.status = TriangulationStatus::kIllConditioned;
    return res;
  }
  if (max_parallax < params.min_parallax_rad) {
    res.status = TriangulationStatus::kLowParallax;
    return res;
  }
  if (max_baseline < params.min_baseline) {
    res.status = TriangulationStatus::kLowBaseline;
    return res;
  }
  const Eigen::Vector3d p_A0 = A.ldlt().solve(b);
  if (!(p_A0.z() > params.min_depth) || !(p_A0.z() < params.max_depth)) {
    res.status = TriangulationStatus::kBadDepth;
    return res;
  }

  // Gauss-Newton (Levenberg damped) in inverse depth of the anchor camera.
  Eigen::Vector3d abr(p_A0.x() / p_A0.z(), p_A0.y() / p_A0.z(), 1.0 / p_A0.z());
  // The system at an accepted candidate is computed together with its cost and reused.
  Eigen::Matrix3d H;
  Eigen::Vector3d g;
  double max_err = 0.0;
  double cost = cost_and_normal_equations(rays, rel, abr, &H, &g, &max_err);
  double lambda = 1e-6;
  for (int it = 0; it < params.gn_iterations && std::isfinite(cost); ++it) {
    res.iterations = it + 1;
    const double prev_cost = cost;
    bool accepted = false;
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    for (int tries = 0; tries < 10 && !accepted; ++tries) {
      Eigen::Matrix3d Hd = H;
      Hd.diagonal() *= (1.0 + lambda);
      step = Hd.ldlt().solve(g);
      const Eigen::Vector3d cand = abr + step;
      Eigen::Matrix3d H_cand;
      Eigen::Vector3d g_cand;
      double max_err_cand = 0.0;
      const double c = cand.z() > 0.0 ? cost_and_normal_equations(rays, rel, cand, &H_cand,
                                                                  &g_cand, &max_err_cand)
                                      : std::numeric_limits<double>::infinity();
      if (c <= cost) {
        abr = cand;
        cost = c;
        max_err = max_err_cand;
        H = H_cand;
        g = g_cand;
        lambda = std::max(lambda * 0.1, 1e-10);
        accepted = true;
      } else {
        lambda *= 10.0;
      }
    }
    // Converged: tiny step, or the cost no longer decreases measurably.
    if (!accepted || step.norm() < params.gn_tolerance || prev_cost - cost <= 1e-12 * prev_cost) {
      break;
    }
  }

  if (!(abr.z() > 0.0)) {
    res.status = TriangulationStatus::kBadDepth;
    return res;
  }
  const Eigen::Vector3d p_A = Eigen::Vector3d(abr.x(), abr.y(), 1.0) / abr.z();
  if (!(p_A.z() > params.min_depth) || !(p_A.z() < params.max_depth)) {
    res.status = TriangulationStatus::kBadDepth;
    return res;
  }
  for (const RelativePose& rp : rel) {
    if (!((rp.R_CA * p_A + rp.p_CA).z() > params.min_depth)) {
      res.status = TriangulationStatus::kBadDepth;
      return res;
    }
  }
  // cost / max_err belong to abr (computed when it was accepted).
  if (!std::isfinite(cost)) {
    cost = reprojection_cost(rays, rel, abr, &max_err);
  }
  res.max_reproj_error = max_err;
  res.rms_reproj_error = std::sqrt(cost / static_cast<double>(rays.size()));
  res.p_W = R_WA * p_A + p_WA;
  if (!(res.max_reproj_error <= params.max_reproj_error_norm)) {
    res.status = TriangulationStatus::kLargeReprojection;
    return res;
  }
  res.status = TriangulationStatus::kOk;
  return res;
}

const char* to_string(TriangulationStatus s) {
  switch (s) {
    case TriangulationStatus::kOk: return "ok";
    case TriangulationStatus::kTooFewObservations: return "too_few_observations";
    case TriangulationStatus::kIllConditioned: return "ill_conditioned";
    case TriangulationStatus::kLowParallax: return "low_parallax";
    case TriangulationStatus::kLowBaseline: return "low_baseline";
    case TriangulationStatus::kBadDepth: return "bad_depth";
    case TriangulationStatus::kLargeReprojection: return "large_reprojection";
  }
  return "unknown";
}

}  // namespace vid::msckf
