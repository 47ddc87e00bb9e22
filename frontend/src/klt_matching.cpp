// KltTracker's matching: temporal (previous -> current left image) and stereo (left -> right).
// A well-predicted point is aligned to its birth patch directly (direct_alignment); the others,
// and every alignment that fails, go through pyramidal KLT followed by the same birth-patch check.
#include <algorithm>
#include <cmath>
#include <limits>

#include "frontend/klt_tracker.h"
#include "frontend/outlier_rejection.h"
#include "frontend/sparse_lk.h"

namespace vid {
namespace {

/// The track nearest to uv (in the left image) among those with `eligible`; nullptr if none.
template <typename Eligible>
const Track* nearest_track(const std::vector<Track>& tracks, cv::Point2f uv, Eligible eligible) {
  const Track* best = nullptr;
  float best_d2 = std::numeric_limits<float>::max();
  for (const Track& t : tracks) {
    if (!eligible(t)) continue;
    const cv::Point2f d = t.uv0 - uv;
    const float d2 = d.x * d.x + d.y * d.y;
    if (d2 < best_d2) best_d2 = d2, best = &t;
  }
  return best;
}

}  // namespace

void KltTracker::predict_rotation(TimeNs t_ns, std::vector<cv::Point2f>* rot,
                                  std::optional<Eigen::Matrix3d>* R_prev_cur) {
  const CameraModel& cam = *cams_[0];
  // Rotation of the current left camera in the previous one: R_C = R_IC^T R_I R_IC.
  const double shift_ns = cam.calib().timeshift_cam_imu_s * 1e9;
  const auto to_imu = [&](TimeNs t) { return t + static_cast<TimeNs>(std::llround(shift_ns)); };
  if (auto R_I = gyro_.rotation(to_imu(*prev_t_), to_imu(t_ns))) {
    const Eigen::Matrix3d R_IC = cam.calib().T_IC.linear();
    *R_prev_cur = R_IC.transpose() * (*R_I) * R_IC;
  }
  stats_.gyro_used = p_.gyro_prediction && R_prev_cur->has_value();
  rot->resize(tracks_.size());
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    (*rot)[i] = tracks_[i].uv0;
    if (!stats_.gyro_used) continue;
    // Rotate the bearing into the current frame (translation ignored) and re-project.
    const Eigen::Vector3d b = (*R_prev_cur)->transpose() *
                              Eigen::Vector3d(tracks_[i].xy0.x(), tracks_[i].xy0.y(), 1.0);
    Eigen::Vector2d uv;
    if (cam.project(b, &uv) && cam.in_image(uv, -p_.lk_window)) {
      (*rot)[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    }
  }
}

std::vector<cv::Point2f> KltTracker::predict_flow(const std::vector<cv::Point2f>& rot) const {
  // What the rotation does not explain (translation parallax) changes little from one frame to
  // the next: rendered vid17/vid18_like, 99.9 % of the predictions within 0.6 px, all within
  // 1 px, against 4 px with the gyro alone. A new track borrows its nearest neighbour's.
  std::vector<cv::Point2f> pred = rot;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const Track* src = tracks_[i].has_flow
                           ? &tracks_[i]
                           : nearest_track(tracks_, tracks_[i].uv0,
                                           [](const Track& t) { return t.has_flow; });
    if (src != nullptr) pred[i] += src->flow;
  }
  return pred;
}

void KltTracker::refine_to_birth(const std::vector<std::uint8_t>& todo,
                                 std::vector<cv::Point2f>* cur, std::vector<std::uint8_t>* ok) {
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    Track& t = tracks_[i];
    if (!todo[i] || !(*ok)[i] || !t.birth) continue;
    PatchWarp w = t.warp;
    const RefineResult r = refiner_.refine(img0_, *t.birth, (*cur)[i], &w);
    stats_.template_iterations += r.iterations;
    if (!r.ok || r.zncc < p_.template_min_zncc ||
        cv::norm(r.uv - (*cur)[i]) > p_.template_max_shift_px) {
      (*ok)[i] = 0;
      ++stats_.template_rejected;
      continue;
    }
    (*cur)[i] = r.uv;
    t.warp = w;
  }
}

void KltTracker::klt_temporal(const std::vector<std::uint8_t>& todo,
                              std::vector<cv::Point2f>* cur, std::vector<std::uint8_t>* ok) {
  std::vector<std::size_t> idx;
  std::vector<cv::Point2f> a, b;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    if (!todo[i]) continue;
    idx.push_back(i);
    a.push_back(tracks_[i].uv0);
    b.push_back((*cur)[i]);
  }
  if (idx.empty()) return;
  stats_.klt_points += static_cast<int>(idx.size());
  // Gyro-predicted points start close: the coarser stop suffices (birth-patch alignment follows).
  const LkParams lk{p_.lk_window, p_.lk_levels,
                    stats_.gyro_used ? p_.lk_predicted_max_iterations : p_.lk_max_iterations,
                    stats_.gyro_used ? p_.lk_predicted_epsilon : p_.lk_epsilon, p_.lk_min_eigen};
  const std::vector<cv::Mat>& prev = prev_pyramid();
  const std::vector<cv::Mat>& now = left_pyramid();
  std::vector<std::uint8_t> st;
  sparse_lk(prev, now, a, &b, &st, lk);
  if (p_.fb_check_px > 0.0) {
    std::vector<cv::Point2f> back = a;
    std::vector<std::uint8_t> st_b;
    sparse_lk(now, prev, b, &back, &st_b, lk);
    for (std::size_t k = 0; k < idx.size(); ++k) {
      if (!st_b[k] || cv::norm(back[k] - a[k]) > p_.fb_check_px) st[k] = 0;
    }
  }
  for (std::size_t k = 0; k < idx.size(); ++k) {
    (*cur)[idx[k]] = b[k];
    (*ok)[idx[k]] = st[k];
  }
  if (p_.template_refinement) refine_to_birth(todo, cur, ok);
}

void KltTracker::track_temporal(TimeNs t_ns) {
  const std::size_t n = tracks_.size();
  stats_.previous = static_cast<int>(n);
  if (n == 0 || !prev_t_) return;
  std::vector<cv::Point2f> rot;
  std::optional<Eigen::Matrix3d> R_prev_cur;
  predict_rotation(t_ns, &rot, &R_prev_cur);
  std::vector<cv::Point2f> cur = direct() ? predict_flow(rot) : rot;

  std::vector<std::uint8_t> ok(n, 0), todo(n, 1);
  if (direct()) {
    const CameraModel& cam = *cams_[0];
    for (std::size_t i = 0; i < n; ++i) {
      Track& t = tracks_[i];
      // Leaving the image: predicted outside the kept area, or where its birth patch no longer
      // fits. No alignment can keep it there and KLT from there almost never finds it inside
      // (fast_yaw: 40 % of the KLT fallbacks, 6 in 1755 kept after KLT): dropped without KLT.
      if (!cam.in_image(Eigen::Vector2d(cur[i].x, cur[i].y), p_.border_px) ||
          (t.birth && !refiner_.fits(img0_.size(), cur[i], t.warp))) {
        todo[i] = 0;
        continue;
      }
      if (!t.birth) continue;
      PatchWarp w = t.warp;
      const RefineResult r = refiner_.refine(img0_, *t.birth, cur[i], &w);
      stats_.template_iterations += r.iterations;
      // Moved further than a good prediction can be off: let KLT search from the prediction.
      if (!r.ok || r.zncc < p_.template_min_zncc ||
          cv::norm(r.uv - cur[i]) > p_.template_max_shift_px) {
        continue;
      }
      cur[i] = r.uv;
      t.warp = w;
      ok[i] = 1;
      todo[i] = 0;
      ++stats_.direct_aligned;
    }
  }
  klt_temporal(todo, &cur, &ok);
  keep_inliers(rot, cur, ok, R_prev_cur, t_ns);
}

void KltTracker::keep_inliers(const std::vector<cv::Point2f>& rot,
                              const std::vector<cv::Point2f>& cur,
                              const std::vector<std::uint8_t>& ok,
                              const std::optional<Eigen::Matrix3d>& R_prev_cur, TimeNs t_ns) {
  const CameraModel& cam = *cams_[0];
  std::vector<std::size_t> idx;
  std::vector<Eigen::Vector2d> x0, x1;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    if (!ok[i]) continue;
    const Eigen::Vector2d uv(cur[i].x, cur[i].y);
    if (!cam.in_image(uv, p_.border_px)) continue;
    Eigen::Vector2d xy;
    if (!cam.undistort(uv, &xy)) continue;
    idx.push_back(i);
    x0.push_back(tracks_[i].xy0);
    x1.push_back(xy);
  }
  stats_.klt_tracked = static_cast<int>(idx.size());

  const double f = 0.5 * (cam.calib().intrinsics[0] + cam.calib().intrinsics[1]);
  std::vector<std::uint8_t> inl(idx.size(), 1);
  if (p_.ransac == RansacMode::kFundamental) {
    inl = ransac_fundamental(x0, x1, p_.ransac_threshold_px / f, p_.ransac_confidence);
  } else if (p_.ransac == RansacMode::kTwoPoint && R_prev_cur) {
    std::vector<Eigen::Vector3d> b0(idx.size()), b1(idx.size());
    for (std::size_t k = 0; k < idx.size(); ++k) {
      b0[k] = Eigen::Vector3d(x0[k].x(), x0[k].y(), 1.0).normalized();
      b1[k] = Eigen::Vector3d(x1[k].x(), x1[k].y(), 1.0).normalized();
    }
    inl = ransac_two_point(b0, b1, *R_prev_cur, p_.ransac_threshold_px / f,
                           p_.ransac_max_iterations, static_cast<std::uint64_t>(t_ns));
  }

  std::vector<Track> kept;
  kept.reserve(idx.size());
  std::vector<std::uint8_t> keep(tracks_.size(), 0);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    if (!inl[k]) continue;
    keep[idx[k]] = 1;
    Track tr = tracks_[idx[k]];
    tr.flow = cur[idx[k]] - rot[idx[k]];
    tr.has_flow = true;
    tr.uv0 = cur[idx[k]];
    tr.xy0 = x1[k];
    ++tr.age;
    kept.push_back(tr);
  }
  // Last frame's new features that did not survive their first frame: their cells rest.
  std::vector<cv::Point2f> lost_at_birth;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    if (!keep[i] && tracks_[i].age == 0) lost_at_birth.push_back(tracks_[i].uv0);
  }
  detector_.first_frame_losses(lost_at_birth);
  tracks_ = std::move(kept);
  stats_.ransac_inliers = static_cast<int>(tracks_.size());
}

void KltTracker::match_stereo() {
  const std::size_t n = tracks_.size();
  std::vector<std::uint8_t> todo(n, 1);
  stats_.stereo_matched = 0;
  for (std::size_t i = 0; i < n; ++i) {
    // A track whose match failed (often: its point is outside the right image) waits.
    Track& t = tracks_[i];
    if (!t.has_right && t.stereo_wait > 0) {
      --t.stereo_wait;
      todo[i] = 0;
    }
  }
  if (direct()) {
    // A track matched last frame starts at its last disparity (which changes by well under a
    // pixel); another one at its nearest matched neighbour's (depth is mostly smooth). The birth
    // patch (in its current shape) is aligned there directly; KLT below if that fails.
    // Tracks are marked matched after the loop, so every guess comes from last frame's matches.
    std::vector<std::uint8_t> aligned(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      Track& t = tracks_[i];
      if (!todo[i] || !t.birth) continue;
      const Track* src =
          t.has_right ? &t
                      : nearest_track(tracks_, t.uv0, [](const Track& o) { return o.has_right; });
      if (src == nullptr) continue;
      const cv::Point2f guess = t.uv0 + src->right_offset;
      PatchWarp w = t.warp;
      const RefineResult r = refiner_.refine(img1_, *t.birth, guess, &w);
      Eigen::Vector2d xy1;
      if (!r.ok || r.zncc < p_.template_min_zncc ||
          cv::norm(r.uv - guess) > p_.template_max_shift_px ||
          !stereo_->accept(t.uv0, t.xy0, r.uv, &xy1)) {
        continue;
      }
      t.uv1 = r.uv;
      t.xy1 = xy1;
      todo[i] = 0;
      aligned[i] = 1;
      ++stats_.stereo_direct;
      ++stats_.stereo_matched;
    }
    for (std::size_t i = 0; i < n; ++i) {
      Track& t = tracks_[i];
      if (!aligned[i]) continue;
      t.has_right = true;
      t.right_offset = t.uv1 - t.uv0;
    }
  }
  klt_stereo(todo);
}

void KltTracker::klt_stereo(const std::vector<std::uint8_t>& todo) {
  std::vector<std::size_t> idx;
  std::vector<cv::Point2f> uv0, guess;
  std::vector<std::uint8_t> close;
  std::vector<Eigen::Vector2d> xy0;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    if (!todo[i]) continue;
    const Track& t = tracks_[i];
    idx.push_back(i);
    uv0.push_back(t.uv0);
    xy0.push_back(t.xy0);
    // Last frame's disparity is the best guess; new or unmatched tracks start at infinity.
    guess.push_back(t.has_right ? t.uv0 + t.right_offset : stereo_->infinity_guess(t.xy0));
    close.push_back(t.has_right ? 1 : 0);
  }
  if (idx.empty()) return;
  stats_.klt_points += static_cast<int>(idx.size());
  std::vector<cv::Point2f> uv1;
  std::vector<Eigen::Vector2d> xy1;
  std::vector<std::uint8_t> ok;
  stereo_->match(left_pyramid(), right_pyramid(), uv0, xy0, guess, &close, &uv1, &xy1, &ok);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    Track& t = tracks_[idx[k]];
    t.has_right = ok[k] != 0;
    // The epipolar check cannot see a match that slid along the epipolar line: align the
    // birth patch (in its current shape) on the right image too; it must correlate, stay
    // close to the KLT match and pass the stereo checks again.
    if (t.has_right && p_.template_refinement && t.birth) {
      PatchWarp w = t.warp;
      const RefineResult r = refiner_.refine(img1_, *t.birth, uv1[k], &w);
      Eigen::Vector2d x1;
      t.has_right = r.ok && r.zncc >= p_.template_min_zncc &&
                    cv::norm(r.uv - uv1[k]) <= p_.template_max_shift_px &&
                    stereo_->accept(t.uv0, t.xy0, r.uv, &x1);
      if (t.has_right) {
        uv1[k] = r.uv;
        xy1[k] = x1;
      }
    }
    if (t.has_right) {
      t.uv1 = uv1[k];
      t.right_offset = t.uv1 - t.uv0;
      t.xy1 = xy1[k];
      ++stats_.stereo_matched;
    } else {
      t.stereo_wait = p_.stereo_retry_frames;
    }
  }
}

}  // namespace vid
