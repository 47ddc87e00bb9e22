#pragma once
/// @file triangulation.h
/// @brief Feature triangulation: linear midpoint over all observations in the anchor camera
/// frame, then Gauss-Newton in inverse depth, with depth / conditioning / reprojection checks.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "vio_core/msckf/msckf_types.h"

namespace vid::msckf {

/// @brief One observation with the pose of its camera in W.
struct CameraRay {
  Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WC = Eigen::Vector3d::Zero();
  Eigen::Vector2d uv_norm = Eigen::Vector2d::Zero();
};

/// @brief Why a triangulation failed (kOk on success).
enum class TriangulationStatus {
  kOk,
  kTooFewObservations,
  kIllConditioned,
  kLowParallax,
  kLowBaseline,
  kBadDepth,
  kLargeReprojection,
};

/// @brief Result of triangulate(): the point in W and diagnostics.
struct TriangulationResult {
  TriangulationStatus status = TriangulationStatus::kTooFewObservations;
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  double condition = 0.0;          ///< condition number of the linear system
  double max_reproj_error = 0.0;   ///< largest per-observation error, normalized units
  double rms_reproj_error = 0.0;   ///< RMS per-observation error, normalized units
  int iterations = 0;              ///< Gauss-Newton iterations done
  bool ok() const { return status == TriangulationStatus::kOk; }
};

/// @brief Triangulate a point seen by rays[0..n); rays[0] is the anchor camera.
TriangulationResult triangulate(const std::vector<CameraRay>& rays,
                                const TriangulationParams& params);

/// @brief Residual Jacobian of one observation w.r.t. the inverse-depth parameters
/// (alpha, beta, rho) of the anchor (p_A = [alpha, beta, 1] / rho), with the observing
/// camera's pose relative to the anchor (R_CA, p_CA: p_C = R_CA p_A + p_CA). Returns the
/// predicted normalized coordinates; false if the point is behind the camera.
bool inverse_depth_projection(const Eigen::Vector3d& abr, const Eigen::Matrix3d& R_CA,
                              const Eigen::Vector3d& p_CA, Eigen::Vector2d* z,
                              Eigen::Matrix<double, 2, 3>* J);

/// @brief Short name of a status, for logs.
const char* to_string(TriangulationStatus s);

}  // namespace vid::msckf
