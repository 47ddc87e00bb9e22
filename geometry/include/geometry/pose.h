#pragma once
/// @file pose.h
/// @brief The rigid pose type of every module: rotation + position of one frame in another.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vid {

/// @brief Pose T_AB of frame B in frame A: x_A = q_AB * x_B + p_AB (Hamilton unit quaternion,
/// p_AB = origin of B in A). The frames are in the name of the variable that holds it
/// (T_WI: IMU in world, T_IC: camera in IMU), so the members are plain q and p.
struct Pose {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< q_AB
  Eigen::Vector3d p = Eigen::Vector3d::Zero();            ///< p_AB [m]

  /// @brief R_AB.
  Eigen::Matrix3d R() const { return q.toRotationMatrix(); }
  /// @brief The same transform as an Eigen::Isometry3d.
  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R();
    T.translation() = p;
    return T;
  }
};

}  // namespace vid
