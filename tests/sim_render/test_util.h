#pragma once
// Shared helpers of the sim_render tests.
#include <Eigen/Geometry>
#include <cmath>

#include "types/calibration.h"

namespace vid::sim::test {

/// VID-Dataset intrinsics (docs/design.md §6) with a clearly non-zero radtan distortion.
inline CameraCalib vid_calib_distorted(int cam_id = 0) {
  CameraCalib c;
  c.cam_id = cam_id;
  c.width = 640;
  c.height = 480;
  c.intrinsics << 382.59014892578125, 382.59014892578125, 323.421142578125, 242.06617736816406;
  c.distortion = DistortionModel::kRadTan;
  c.distortion_coeffs << -0.12, 0.03, 0.0008, -0.0005;
  return c;
}

/// Camera pose at p_W looking at target_W (z_C forward, x_C right, y_C down; W z is up).
inline Eigen::Isometry3d look_at(const Eigen::Vector3d& p_W, const Eigen::Vector3d& target_W,
                                 double roll = 0.0) {
  const Eigen::Vector3d z = (target_W - p_W).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, y, z;
  T.linear() = T.linear() * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = p_W;
  return T;
}

}  // namespace vid::sim::test
