#pragma once
/// @file outlier_rejection.h
/// @brief Temporal outlier rejection between two frames: RANSAC on the fundamental matrix of
/// undistorted normalized points, or a 2-point RANSAC for the translation direction given the
/// gyro rotation.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace vid {

/// @brief Inlier flags of a fundamental-matrix RANSAC on normalized points x0 <-> x1.
/// @param threshold  epipolar distance threshold in normalized units (px / focal length)
/// Fewer than 8 pairs: all are reported inliers (nothing to test against).
std::vector<std::uint8_t> ransac_fundamental(const std::vector<Eigen::Vector2d>& x0,
                                             const std::vector<Eigen::Vector2d>& x1,
                                             double threshold, double confidence);

/// @brief Inlier flags of a 2-point RANSAC for t in t . (b0 x R_01 b1) = 0 with R_01 known.
/// @param b0, b1      unit bearings in the previous / current camera frame
/// @param R_01        orientation of the current camera in the previous one (from the gyro)
/// @param threshold   |t . (b0 x R b1)| threshold (about px / focal length)
/// @param seed        RANSAC sample seed (deterministic)
std::vector<std::uint8_t> ransac_two_point(const std::vector<Eigen::Vector3d>& b0,
                                           const std::vector<Eigen::Vector3d>& b1,
                                           const Eigen::Matrix3d& R_01, double threshold,
                                           int max_iterations, std::uint64_t seed);

}  // namespace vid
