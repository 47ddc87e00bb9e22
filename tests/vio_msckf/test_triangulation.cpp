/// Triangulation: exact recovery without noise, accuracy with noise, and every rejection.

#include <gtest/gtest.h>

#include <algorithm>

#include "synthetic_scene.h"
#include "vio_core/msckf/triangulation.h"

namespace vid::msckf {
namespace {

using testing::make_scene;
using testing::Scene;
using testing::SceneOptions;

std::vector<CameraRay> rays_of(const Scene& s, const FeatureTrack& tr) {
  std::vector<CameraRay> rays;
  for (const TrackObservation& o : tr.obs) {
    const ClonePose* c = nullptr;
    for (const ClonePose& cc : s.clones_true) {
      if (cc.t_ns == o.t_ns) c = &cc;
    }
    const Eigen::Isometry3d& T_IC = s.extrinsics[o.cam_id].T_IC;
    rays.push_back({c->R_WI * T_IC.linear(), c->p_WI + c->R_WI * T_IC.translation(), o.uv_norm});
  }
  return rays;
}

/// A camera at p looking along +z of W (R_WC = I).
CameraRay ray_at(const Eigen::Vector3d& p_WC, const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d d = p_W - p_WC;
  return {Eigen::Matrix3d::Identity(), p_WC, d.head<2>() / d.z()};
}

TEST(Triangulation, RecoversPointExactlyWithoutNoise) {
  for (bool stereo : {false, true}) {
    SceneOptions opt;
    opt.stereo = stereo;
    const Scene s = make_scene(opt);
    for (std::size_t f = 0; f < s.tracks.size(); ++f) {
      const TriangulationResult res = triangulate(rays_of(s, s.tracks[f]), TriangulationParams{});
      ASSERT_TRUE(res.ok()) << to_string(res.status);
      EXPECT_LT((res.p_W - s.landmarks_W[f]).norm(), 1e-9 * s.landmarks_W[f].norm());
      EXPECT_LT(res.max_reproj_error, 1e-10);
    }
  }
}

TEST(Triangulation, AccurateWithPixelNoise) {
  SceneOptions opt;
  opt.pixel_sigma_norm = 1.0 / opt.focal;  // 1 px
  opt.num_features = 200;
  const Scene s = make_scene(opt);
  std::vector<double> rel_err;
  for (std::size_t f = 0; f < s.tracks.size(); ++f) {
    const auto rays = rays_of(s, s.tracks[f]);
    const TriangulationResult res = triangulate(rays, TriangulationParams{});
    ASSERT_TRUE(res.ok()) << to_string(res.status);
    const double depth = (s.landmarks_W[f] - rays[0].p_WC).norm();
    double baseline = 0.0;
    for (const CameraRay& r : rays) baseline = std::max(baseline, (r.p_WC - rays[0].p_WC).norm());
    const double err = (res.p_W - s.landmarks_W[f]).norm();
    rel_err.push_back(err / depth);
    // First-order depth error of a two-view triangulation is depth^2 sigma / baseline; with
    // 22 rays it must stay below a few times that.
    EXPECT_LT(err, 4.0 * depth * depth * opt.pixel_sigma_norm / baseline) << "feature " << f;
    // Gauss-Newton reaches the noise level: residuals of a few sigma at most.
    EXPECT_LT(res.max_reproj_error, 5.0 * opt.pixel_sigma_norm);
  }
  std::sort(rel_err.begin(), rel_err.end());
  // 22 rays over a 0.8 m trajectory + 0.11 m stereo baseline, landmarks 3-7 m away:
  // depth^2 sigma / baseline is 1-4 % of the depth.
  EXPECT_LT(rel_err[rel_err.size() / 2], 0.02);
  EXPECT_LT(rel_err.back(), 0.10);
}

TEST(Triangulation, GaussNewtonImprovesOnLinearStart) {
  // With noise, the midpoint solution is not the reprojection optimum; GN must lower the
  // sum of squared reprojection errors.
  SceneOptions opt;
  opt.pixel_sigma_norm = 2.0 / opt.focal;
  opt.num_features = 30;
  const Scene s = make_scene(opt);
  for (const FeatureTrack& tr : s.tracks) {
    TriangulationParams p0;
    p0.gn_iterations = 0;
    TriangulationParams p;
    const auto rays = rays_of(s, tr);
    const TriangulationResult lin = triangulate(rays, p0);
    const TriangulationResult gn = triangulate(rays, p);
    ASSERT_TRUE(lin.ok());
    ASSERT_TRUE(gn.ok());
    EXPECT_EQ(lin.iterations, 0);
    EXPECT_GT(gn.iterations, 0);
    EXPECT_LT(gn.rms_reproj_error, lin.rms_reproj_error);
  }
}

TEST(Triangulation, RejectsDegenerateGeometry) {
  const Eigen::Vector3d p_W(0.3, -0.2, 5.0);
  TriangulationParams params;

  // One observation only.
  EXPECT_EQ(triangulate({ray_at(Eigen::Vector3d::Zero(), p_W)}, params).status,
            TriangulationStatus::kTooFewObservations);

  // Same camera centre: no baseline, infinite condition number.
  EXPECT_EQ(triangulate({ray_at(Eigen::Vector3d::Zero(), p_W),
                         ray_at(Eigen::Vector3d::Zero(), p_W)}, params).status,
            TriangulationStatus::kIllConditioned);

  // Good geometry passes.
  const std::vector<CameraRay> good = {ray_at(Eigen::Vector3d(0, 0, 0), p_W),
                                       ray_at(Eigen::Vector3d(0.5, 0, 0), p_W),
                                       ray_at(Eigen::Vector3d(1.0, 0.2, 0), p_W)};
  const TriangulationResult ok = triangulate(good, params);
  ASSERT_TRUE(ok.ok()) << to_string(ok.status);
  EXPECT_LT((ok.p_W - p_W).norm(), 1e-10);

  // Parallax / baseline thresholds.
  TriangulationParams strict = params;
  strict.min_parallax_rad = 0.5;
  EXPECT_EQ(triangulate(good, strict).status, TriangulationStatus::kLowParallax);
  strict = params;
  strict.min_baseline = 2.0;
  EXPECT_EQ(triangulate(good, strict).status, TriangulationStatus::kLowBaseline);

  // Too far for max_depth.
  strict = params;
  strict.max_depth = 4.0;
  EXPECT_EQ(triangulate(good, strict).status, TriangulationStatus::kBadDepth);

  // Lines intersecting behind the cameras.
  const Eigen::Vector3d behind(0.3, -0.2, -5.0);
  std::vector<CameraRay> back;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.5, 0, 0),
                                  Eigen::Vector3d(1.0, 0.2, 0)}) {
    back.push_back(ray_at(c, behind));
  }
  EXPECT_EQ(triangulate(back, params).status, TriangulationStatus::kBadDepth);

  // Inconsistent rays (one observation 0.2 off): large reprojection error.
  std::vector<CameraRay> bad = good;
  bad.push_back(ray_at(Eigen::Vector3d(0.2, 0.5, 0), p_W));
  bad.push_back(ray_at(Eigen::Vector3d(0.8, -0.4, 0), p_W));
  bad[2].uv_norm.x() += 0.2;
  EXPECT_EQ(triangulate(bad, params).status, TriangulationStatus::kLargeReprojection);
}

}  // namespace
}  // namespace vid::msckf
