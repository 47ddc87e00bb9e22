// Camera models: agreement with OpenCV (projectPoints / undistortPoints, cv::fisheye) over a
// grid covering the image, round trips, and analytic Jacobians vs numeric differentiation.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <vector>

#include "frontend/camera_model.h"

namespace vid {
namespace {

CameraCalib radtan_calib() {
  CameraCalib c;
  c.width = 752;
  c.height = 480;
  c.intrinsics << 458.654, 457.296, 367.215, 248.375;  // EuRoC cam0
  c.distortion = DistortionModel::kRadTan;
  c.distortion_coeffs << -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05;
  return c;
}

CameraCalib equidistant_calib() {
  CameraCalib c;
  c.width = 640;
  c.height = 480;
  c.intrinsics << 380.8, 381.2, 322.1, 241.3;
  c.distortion = DistortionModel::kEquidistant;
  c.distortion_coeffs << -0.012, 0.041, -0.035, 0.011;
  return c;
}

cv::Matx33d k_matrix(const CameraCalib& c) {
  return {c.intrinsics[0], 0, c.intrinsics[2], 0, c.intrinsics[1], c.intrinsics[3], 0, 0, 1};
}

/// Pixels on a grid covering the whole image (edges included).
std::vector<Eigen::Vector2d> pixel_grid(const CameraCalib& c, int n = 25) {
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      out.emplace_back(-0.5 + (c.width) * i / (n - 1.0), -0.5 + (c.height) * j / (n - 1.0));
    }
  }
  return out;
}

TEST(CameraModel, CreateRejectsBadCalibration) {
  CameraCalib c = radtan_calib();
  c.intrinsics[0] = 0.0;
  EXPECT_THROW(CameraModel::create(c), std::invalid_argument);
  c = radtan_calib();
  c.width = 0;
  EXPECT_THROW(CameraModel::create(c), std::invalid_argument);
}

TEST(CameraModel, ProjectRejectsPointsBehind) {
  const auto cam = CameraModel::create(radtan_calib());
  Eigen::Vector2d uv;
  EXPECT_FALSE(cam->project({0.1, 0.2, -1.0}, &uv));
  EXPECT_FALSE(cam->project({0.1, 0.2, 0.0}, &uv));
  EXPECT_TRUE(cam->project({0.1, 0.2, 1.0}, &uv));
}

TEST(CameraModel, InImage) {
  const auto cam = CameraModel::create(radtan_calib());
  EXPECT_TRUE(cam->in_image({0.0, 0.0}));
  EXPECT_FALSE(cam->in_image({0.0, 0.0}, 5.0));
  EXPECT_TRUE(cam->in_image({751.0, 479.0}));
  EXPECT_FALSE(cam->in_image({760.0, 100.0}));
}

class CameraModelBoth : public ::testing::TestWithParam<DistortionModel> {
 protected:
  CameraCalib calib() const {
    return GetParam() == DistortionModel::kRadTan ? radtan_calib() : equidistant_calib();
  }
};

TEST_P(CameraModelBoth, AgreesWithOpenCvProjection) {
  const CameraCalib c = calib();
  const auto cam = CameraModel::create(c);
  std::vector<cv::Point3d> pts;
  for (const auto& uv : pixel_grid(c)) {
    Eigen::Vector2d xy;
    ASSERT_TRUE(cam->undistort(uv, &xy));
    pts.emplace_back(xy.x() * 2.5, xy.y() * 2.5, 2.5);
  }
  std::vector<cv::Point2d> cv_uv;
  const cv::Vec4d d(c.distortion_coeffs[0], c.distortion_coeffs[1], c.distortion_coeffs[2],
                    c.distortion_coeffs[3]);
  if (GetParam() == DistortionModel::kRadTan) {
    cv::projectPoints(pts, cv::Vec3d::zeros(), cv::Vec3d::zeros(), k_matrix(c), d, cv_uv);
  } else {
    cv::fisheye::projectPoints(pts, cv_uv, cv::Vec3d::zeros(), cv::Vec3d::zeros(), k_matrix(c),
                               d);
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam->project({pts[i].x, pts[i].y, pts[i].z}, &uv));
    EXPECT_NEAR(uv.x(), cv_uv[i].x, 1e-9) << "point " << i;
    EXPECT_NEAR(uv.y(), cv_uv[i].y, 1e-9) << "point " << i;
  }
}

TEST_P(CameraModelBoth, AgreesWithOpenCvUndistortion) {
  const CameraCalib c = calib();
  const auto cam = CameraModel::create(c);
  const auto grid = pixel_grid(c);
  std::vector<cv::Point2d> src;
  for (const auto& uv : grid) src.emplace_back(uv.x(), uv.y());
  std::vector<cv::Point2d> dst;
  const cv::Vec4d d(c.distortion_coeffs[0], c.distortion_coeffs[1], c.distortion_coeffs[2],
                    c.distortion_coeffs[3]);
  // OpenCV's fixed-point iterations need tight criteria to reach 1e-9 px.
  const cv::TermCriteria crit(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 1000, 1e-15);
  if (GetParam() == DistortionModel::kRadTan) {
    cv::undistortPoints(src, dst, k_matrix(c), d, cv::noArray(), cv::noArray(), crit);
  } else {
    cv::fisheye::undistortPoints(src, dst, k_matrix(c), d, cv::noArray(), cv::noArray(), crit);
  }
  const double fu = c.intrinsics[0], fv = c.intrinsics[1];
  for (std::size_t i = 0; i < grid.size(); ++i) {
    Eigen::Vector2d xy;
    ASSERT_TRUE(cam->undistort(grid[i], &xy));
    // Compare in pixels of the undistorted (pinhole) image.
    EXPECT_NEAR(xy.x() * fu, dst[i].x * fu, 1e-9) << "pixel " << grid[i].transpose();
    EXPECT_NEAR(xy.y() * fv, dst[i].y * fv, 1e-9) << "pixel " << grid[i].transpose();
  }
}

TEST_P(CameraModelBoth, UndistortRoundTrip) {
  const CameraCalib c = calib();
  const auto cam = CameraModel::create(c);
  for (const auto& uv : pixel_grid(c, 41)) {
    Eigen::Vector2d xy;
    ASSERT_TRUE(cam->undistort(uv, &xy));
    EXPECT_LT((cam->distort(xy) - uv).norm(), 1e-10);
    Eigen::Vector3d b;
    ASSERT_TRUE(cam->unproject(uv, &b));
    EXPECT_NEAR(b.norm(), 1.0, 1e-12);
    Eigen::Vector2d uv2;
    ASSERT_TRUE(cam->project(b * 3.7, &uv2));
    EXPECT_LT((uv2 - uv).norm(), 1e-9);
  }
}

TEST_P(CameraModelBoth, DistortJacobianMatchesNumeric) {
  const CameraCalib c = calib();
  const auto cam = CameraModel::create(c);
  const double h = 1e-6;
  for (const auto& uv : pixel_grid(c, 9)) {
    Eigen::Vector2d xy;
    ASSERT_TRUE(cam->undistort(uv, &xy));
    const Eigen::Matrix2d J = cam->distort_jacobian(xy);
    Eigen::Matrix2d Jn;
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d e = Eigen::Vector2d::Zero();
      e[k] = h;
      Jn.col(k) = (cam->distort(xy + e) - cam->distort(xy - e)) / (2 * h);
    }
    EXPECT_LT((J - Jn).norm(), 1e-5 * (1.0 + J.norm())) << "at " << uv.transpose();
  }
  // On the optical axis (equidistant special case).
  const Eigen::Matrix2d J0 = cam->distort_jacobian(Eigen::Vector2d::Zero());
  Eigen::Matrix2d Jn0;
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector2d e = Eigen::Vector2d::Zero();
    e[k] = h;
    Jn0.col(k) = (cam->distort(e) - cam->distort(-e)) / (2 * h);
  }
  EXPECT_LT((J0 - Jn0).norm(), 1e-5 * J0.norm());
}

TEST_P(CameraModelBoth, ProjectJacobianMatchesNumeric) {
  const auto cam = CameraModel::create(calib());
  const double h = 1e-6;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, -0.2, 2.0), Eigen::Vector3d(-0.5, 0.4, 1.1),
                                  Eigen::Vector3d(0.01, 0.02, 5.0)}) {
    const Eigen::Matrix<double, 2, 3> J = cam->project_jacobian(p);
    Eigen::Matrix<double, 2, 3> Jn;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[k] = h;
      Eigen::Vector2d a, b;
      ASSERT_TRUE(cam->project(p + e, &a));
      ASSERT_TRUE(cam->project(p - e, &b));
      Jn.col(k) = (a - b) / (2 * h);
    }
    EXPECT_LT((J - Jn).norm(), 1e-5 * (1.0 + J.norm())) << "at " << p.transpose();
  }
}

INSTANTIATE_TEST_SUITE_P(Models, CameraModelBoth,
                         ::testing::Values(DistortionModel::kRadTan, DistortionModel::kEquidistant));

}  // namespace
}  // namespace vid
