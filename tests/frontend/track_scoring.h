#pragma once
// Scores the KLT frontend on a rendered simulator sequence: each track's first observation is
// ray-cast into the simulator's scene (ground-truth pose interpolated to the frame time) to
// find the 3-D point it started on; later observations are compared with that point's true
// projection. Stereo matches are compared with the right-camera projection of the point seen
// by the left observation in the same frame.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "frontend/klt_tracker.h"
#include "io/dataset_reader.h"
#include "sim/render/scene.h"

namespace vid::test {

struct TrackScore {
  std::size_t frames = 0;
  double mean_features = 0;       ///< live left tracks per frame
  double median_features = 0;     ///< ... median over frames
  double median_err_px = 0;       ///< over all observations with age > 0
  double p90_err_px = 0;
  std::size_t tracks = 0;         ///< tracks scored (start point found)
  double drift_fraction = 0;      ///< tracks ever > 3 px from their point
  double mean_track_length = 0;   ///< frames per finished-or-live track
  double median_disp_err_px = 0;  ///< stereo: right observation vs true right projection
  double stereo_fraction = 0;     ///< right matches / left tracks
  double disp_outliers = 0;       ///< fraction of right observations > 1 px from the truth
  double kept_fraction = 0;       ///< sum kept / sum previous, frame to frame
  double mean_ms = 0;
  /// Errors by track age: 1, 2-5, 6-20, 21-60, > 60 frames (for the report).
  std::array<std::vector<double>, 5> err_by_age;
  /// Drifters (> 3 px): how many were born on a depth discontinuity (the depth seen 4 px away
  /// differs by > 10%), and a few examples for the report.
  std::size_t drifted = 0, drifted_at_discontinuity = 0, born_at_discontinuity = 0;
  struct Drifter {
    std::uint64_t id;
    double u, v, depth;
    int age_at_3px;
    bool discontinuity;
  };
  std::vector<Drifter> drifter_examples;
};

/// Ground-truth pose interpolation (linear position, slerp orientation).
class PoseTrack {
 public:
  void add(const GroundTruthSample& s) { gt_.push_back(s); }
  bool at(TimeNs t, Eigen::Isometry3d* T_WI) const {
    if (gt_.size() < 2 || t < gt_.front().t_ns || t > gt_.back().t_ns) return false;
    auto it = std::lower_bound(gt_.begin(), gt_.end(), t,
                               [](const GroundTruthSample& s, TimeNs v) { return s.t_ns < v; });
    if (it == gt_.begin()) ++it;
    const auto& b = *it;
    const auto& a = *(it - 1);
    const double f = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
    T_WI->setIdentity();
    T_WI->linear() = a.T_WI.q.slerp(f, b.T_WI.q).toRotationMatrix();
    T_WI->translation() = (1 - f) * a.T_WI.p + f * b.T_WI.p;
    return true;
  }

 private:
  std::vector<GroundTruthSample> gt_;
};

inline double median_of(std::vector<double> v) {
  if (v.empty()) return 1e9;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// @p R_GS: the simulator's rotation from the scene world to the written ground-truth world
/// (Simulator::R_GS; identity unless the scenario sets groundtruth.initial_heading_deg).
inline TrackScore score_sequence(const std::filesystem::path& dataset, const FrontendParams& params,
                                 const sim::Scene& scene, bool stereo,
                                 double kept_min_rate = 0.0,
                                 const Eigen::Matrix3d& R_GS = Eigen::Matrix3d::Identity()) {
  // Pass 1: ground truth and calibration.
  PoseTrack gt;
  std::vector<CameraCalib> cams;
  {
    io::ReaderOptions o;
    o.read_images = false;
    o.read_features = false;
    io::DatasetReader r(dataset, o);
    cams = r.calibration().cameras;
    while (auto m = r.next()) {
      if (auto* g = std::get_if<GroundTruthSample>(&*m)) gt.add(*g);
    }
  }
  if (!stereo) cams.resize(1);
  KltTracker tracker(params, cams);
  const CameraModel& cam0 = tracker.camera(0);

  struct Born {
    bool ok = false;
    Eigen::Vector3d p_W;
    int length = 0;
    double max_err = 0;
    double u = 0, v = 0, depth = 0;
    int age_at_3px = -1;
    bool discontinuity = false;
  };
  std::map<std::uint64_t, Born> born;
  std::vector<double> errs, disp_errs, features_per_frame;
  TrackScore s;
  double kept = 0, prev = 0, feat = 0, ms = 0, n_right = 0, last_rate = 0;

  io::ReaderOptions o;
  o.read_features = false;
  o.read_groundtruth = false;
  io::DatasetReader reader(dataset, o);
  while (auto m = reader.next()) {
    if (auto* imu = std::get_if<ImuSample>(&*m)) {
      tracker.add_imu(*imu);
      last_rate = imu->gyro_I.norm();
      continue;
    }
    auto* frame = std::get_if<ImageFrame>(&*m);
    if (!frame) continue;
    Eigen::Isometry3d T_WI;  // W: the scene's world
    if (!gt.at(frame->t_ns, &T_WI)) continue;
    T_WI.linear() = R_GS.transpose() * T_WI.linear();
    T_WI.translation() = R_GS.transpose() * T_WI.translation();
    cv::Mat left, right;
    for (const auto& ref : frame->images) {
      if (ref.cam_id == cams[0].cam_id) left = cv::imread(ref.path, cv::IMREAD_GRAYSCALE);
      if (stereo && ref.cam_id == cams[1].cam_id) right = cv::imread(ref.path, cv::IMREAD_GRAYSCALE);
    }
    tracker.process(frame->t_ns, left, right);
    const TrackerStats& st = tracker.stats();
    // Frame-to-frame survival, counted only while rotating at least kept_min_rate [rad/s].
    if (s.frames > 0 && last_rate >= kept_min_rate) {
      kept += st.ransac_inliers;
      prev += st.previous;
    }
    ++s.frames;
    feat += static_cast<double>(tracker.tracks().size());
    features_per_frame.push_back(static_cast<double>(tracker.tracks().size()));
    ms += st.ms_total;
    const Eigen::Isometry3d T_WC0 = T_WI * cams[0].T_IC;
    const Eigen::Isometry3d T_C0W = T_WC0.inverse();
    for (const auto& t : tracker.tracks()) {
      Born& b = born[t.id];
      const Eigen::Vector3d dir_W = T_WC0.linear() * Eigen::Vector3d(t.xy0.x(), t.xy0.y(), 1.0);
      if (t.age == 0) {
        const auto hit = scene.raycast(T_WC0.translation(), dir_W);
        b.ok = hit.has_value();
        if (b.ok) {
          b.p_W = *hit;
          b.u = t.uv0.x;
          b.v = t.uv0.y;
          b.depth = (T_C0W * *hit).z();
          // Depth 4 px left/right/up/down: a > 10% jump means the patch straddles two surfaces.
          for (const auto& d : {Eigen::Vector2d(4, 0), Eigen::Vector2d(-4, 0),
                                Eigen::Vector2d(0, 4), Eigen::Vector2d(0, -4)}) {
            Eigen::Vector3d bearing;
            if (!cam0.unproject(Eigen::Vector2d(t.uv0.x, t.uv0.y) + d, &bearing)) continue;
            const auto h2 = scene.raycast(T_WC0.translation(), T_WC0.linear() * bearing);
            if (!h2 || std::abs((T_C0W * *h2).z() - b.depth) > 0.1 * b.depth) b.discontinuity = true;
          }
        }
      } else if (b.ok) {
        Eigen::Vector2d uv_true;
        if (cam0.project(T_C0W * b.p_W, &uv_true)) {
          const double e = (uv_true - Eigen::Vector2d(t.uv0.x, t.uv0.y)).norm();
          errs.push_back(e);
          b.max_err = std::max(b.max_err, e);
          if (e > 3.0 && b.age_at_3px < 0) b.age_at_3px = t.age;
          const int bin = t.age < 2 ? 0 : t.age < 6 ? 1 : t.age < 21 ? 2 : t.age < 61 ? 3 : 4;
          s.err_by_age[static_cast<std::size_t>(bin)].push_back(e);
        }
      }
      ++b.length;
      if (stereo && t.has_right) {
        ++n_right;
        // The point the left observation sees now, projected into the right camera.
        const auto hit = scene.raycast(T_WC0.translation(), dir_W);
        if (hit) {
          const Eigen::Isometry3d T_C1W = (T_WI * cams[1].T_IC).inverse();
          Eigen::Vector2d uv_r;
          if (tracker.camera(1).project(T_C1W * *hit, &uv_r)) {
            disp_errs.push_back((uv_r - Eigen::Vector2d(t.uv1.x, t.uv1.y)).norm());
          }
        }
      }
    }
  }
  std::size_t drifted = 0, scored = 0;
  double len = 0;
  for (const auto& [id, b] : born) {
    len += b.length;
    if (!b.ok) continue;
    ++scored;
    s.born_at_discontinuity += b.discontinuity ? 1 : 0;
    if (b.max_err > 3.0) {
      ++drifted;
      s.drifted_at_discontinuity += b.discontinuity ? 1 : 0;
      if (s.drifter_examples.size() < 8) {
        s.drifter_examples.push_back({id, b.u, b.v, b.depth, b.age_at_3px, b.discontinuity});
      }
    }
  }
  s.drifted = drifted;
  s.tracks = scored;
  s.drift_fraction = scored ? static_cast<double>(drifted) / static_cast<double>(scored) : 1.0;
  s.mean_track_length = born.empty() ? 0 : len / static_cast<double>(born.size());
  s.mean_features = s.frames ? feat / static_cast<double>(s.frames) : 0;
  s.median_features = features_per_frame.empty() ? 0 : median_of(features_per_frame);
  s.mean_ms = s.frames ? ms / static_cast<double>(s.frames) : 0;
  s.median_err_px = median_of(errs);
  if (!errs.empty()) {
    std::sort(errs.begin(), errs.end());
    s.p90_err_px = errs[errs.size() * 9 / 10];
  }
  s.median_disp_err_px = median_of(disp_errs);
  if (!disp_errs.empty()) {
    s.disp_outliers = static_cast<double>(std::count_if(disp_errs.begin(), disp_errs.end(),
                                                        [](double e) { return e > 1.0; })) /
                      static_cast<double>(disp_errs.size());
  }
  s.stereo_fraction = feat > 0 ? n_right / feat : 0;
  s.kept_fraction = prev > 0 ? kept / prev : 0;
  return s;
}

inline void print_score(const char* name, const TrackScore& s) {
  std::printf(
      "[%s] frames %zu, features/frame %.1f (median %.0f), median err %.3f px (p90 %.3f), tracks %zu, "
      "drift>3px %.2f%%, mean length %.1f frames, stereo %.1f%%, median disparity err %.3f px "
      "(> 1 px: %.2f%%), "
      "kept frame-to-frame %.1f%%, %.2f ms/frame\n",
      name, s.frames, s.mean_features, s.median_features, s.median_err_px, s.p90_err_px, s.tracks,
      100 * s.drift_fraction, s.mean_track_length, 100 * s.stereo_fraction, s.median_disp_err_px,
      100 * s.disp_outliers,
      100 * s.kept_fraction, s.mean_ms);
  const char* bins[] = {"1", "2-5", "6-20", "21-60", ">60"};
  std::printf("  median error by track age:");
  for (std::size_t i = 0; i < 5; ++i) {
    std::printf(" [%s] %.3f (n=%zu)", bins[i], median_of(s.err_by_age[i]), s.err_by_age[i].size());
  }
  std::printf("\n");
  std::printf("  drifters: %zu (%zu born on a depth discontinuity; %zu of %zu tracks born on one)\n",
              s.drifted, s.drifted_at_discontinuity, s.born_at_discontinuity, s.tracks);
  for (const auto& d : s.drifter_examples) {
    std::printf("    id %llu born at (%.0f, %.0f) depth %.2f m, > 3 px at age %d%s\n",
                static_cast<unsigned long long>(d.id), d.u, d.v, d.depth, d.age_at_3px,
                d.discontinuity ? ", discontinuity" : "");
  }
}

}  // namespace vid::test
