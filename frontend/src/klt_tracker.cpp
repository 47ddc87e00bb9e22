#include "frontend/klt_tracker.h"

#include <algorithm>
#include <chrono>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>
#include <string>

#include "frontend/outlier_rejection.h"

namespace vid {

KltTracker::KltTracker(const FrontendParams& params, const std::vector<CameraCalib>& cams)
    : p_(params),
      detector_(params),
      refiner_(params.template_half, params.template_iterations, params.template_epsilon_px) {
  if (cams.empty()) throw std::invalid_argument("KltTracker: no camera calibration given");
  for (const auto& c : cams) cams_.push_back(CameraModel::create(c));
  if (cams_.size() >= 2 && p_.stereo) {
    stereo_ = std::make_unique<StereoMatcher>(p_, *cams_[0], *cams_[1]);
  }
  if (p_.equalization == Equalization::kClahe) {
    clahe_ = cv::createCLAHE(p_.clahe_clip_limit, cv::Size(p_.clahe_tile, p_.clahe_tile));
  }
}

void KltTracker::add_imu(const ImuSample& s) { gyro_.add(s); }

cv::Mat KltTracker::prepare(const cv::Mat& img, const CameraModel& cam) const {
  if (img.empty()) throw std::invalid_argument("KltTracker: empty image");
  if (img.cols != cam.width() || img.rows != cam.height()) {
    throw std::invalid_argument("KltTracker: image of camera " +
                                std::to_string(cam.calib().cam_id) + " is " +
                                std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                                ", calibration says " + std::to_string(cam.width()) + "x" +
                                std::to_string(cam.height()));
  }
  cv::Mat gray;
  if (img.channels() == 3) {
    cv::cvtColor(img, gray, cv::COLOR_BGR2GRAY);
  } else if (img.channels() == 1 && img.depth() == CV_8U) {
    gray = img;
  } else {
    throw std::invalid_argument("KltTracker: images must be 8-bit gray or BGR");
  }
  if (p_.equalization == Equalization::kHistogram) {
    cv::Mat eq;
    cv::equalizeHist(gray, eq);
    return eq;
  }
  if (p_.equalization == Equalization::kClahe) {
    cv::Mat eq;
    clahe_->apply(gray, eq);
    return eq;
  }
  return gray;
}

void KltTracker::pyramid(const cv::Mat& img, bool derivatives, std::vector<cv::Mat>* pyr) const {
  // Reuses the vector's buffers frame after frame (same sizes), so no per-frame allocation.
  const int levels = stereo_ ? std::max(p_.lk_levels, p_.stereo_lk_levels) : p_.lk_levels;
  cv::buildOpticalFlowPyramid(img, *pyr, cv::Size(p_.lk_window, p_.lk_window), levels,
                              derivatives);
}

void KltTracker::refine_to_birth(const cv::Mat& img, std::vector<cv::Point2f>* cur,
                                 std::vector<std::uint8_t>* ok) {
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    Track& t = tracks_[i];
    if (!(*ok)[i] || !t.birth) continue;
    PatchWarp w = t.warp;
    const RefineResult r = refiner_.refine(img, *t.birth, (*cur)[i], &w);
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

void KltTracker::track_temporal(const cv::Mat& img, const std::vector<cv::Mat>& pyr,
                                TimeNs t_ns) {
  const CameraModel& cam = *cams_[0];
  const std::size_t n = tracks_.size();
  stats_.previous = static_cast<int>(n);
  if (n == 0 || !prev_t_) return;

  // Rotation of the current left camera in the previous one: R_C = R_IC^T R_I R_IC.
  std::optional<Eigen::Matrix3d> R_prev_cur;
  const double shift_ns = cam.calib().timeshift_cam_imu_s * 1e9;
  const auto to_imu = [&](TimeNs t) { return t + static_cast<TimeNs>(std::llround(shift_ns)); };
  if (auto R_I = gyro_.rotation(to_imu(*prev_t_), to_imu(t_ns))) {
    const Eigen::Matrix3d R_IC = cam.calib().T_IC.linear();
    R_prev_cur = R_IC.transpose() * (*R_I) * R_IC;
  }

  std::vector<cv::Point2f> prev(n), cur(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = tracks_[i].uv0;
    cur[i] = prev[i];
    if (p_.gyro_prediction && R_prev_cur) {
      // Rotate the bearing into the current frame (translation ignored) and re-project.
      const Eigen::Vector3d b = R_prev_cur->transpose() *
                                Eigen::Vector3d(tracks_[i].xy0.x(), tracks_[i].xy0.y(), 1.0);
      Eigen::Vector2d uv;
      if (cam.project(b, &uv) && cam.in_image(uv, -p_.lk_window)) {
        cur[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
      }
    }
  }
  stats_.gyro_used = p_.gyro_prediction && R_prev_cur.has_value();

  const cv::Size win(p_.lk_window, p_.lk_window);
  // Gyro-predicted points start close: the coarser stop suffices (birth-patch alignment follows).
  const cv::TermCriteria crit(
      cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
      stats_.gyro_used ? p_.lk_predicted_max_iterations : p_.lk_max_iterations,
      stats_.gyro_used ? p_.lk_predicted_epsilon : p_.lk_epsilon);
  std::vector<std::uint8_t> st;
  // No error output: OpenCV would spend one more window interpolation per point on it.
  cv::calcOpticalFlowPyrLK(prev_pyr_, pyr, prev, cur, st, cv::noArray(), win, p_.lk_levels, crit,
                           cv::OPTFLOW_USE_INITIAL_FLOW, p_.lk_min_eigen);
  if (p_.fb_check_px > 0.0) {
    std::vector<cv::Point2f> back = prev;
    std::vector<std::uint8_t> st_b;
    cv::calcOpticalFlowPyrLK(pyr, prev_pyr_, cur, back, st_b, cv::noArray(), win, p_.lk_levels, crit,
                             cv::OPTFLOW_USE_INITIAL_FLOW, p_.lk_min_eigen);
    for (std::size_t i = 0; i < n; ++i) {
      if (!st_b[i] || cv::norm(back[i] - prev[i]) > p_.fb_check_px) st[i] = 0;
    }
  }
  if (p_.template_refinement) refine_to_birth(img, &cur, &st);

  std::vector<std::size_t> idx;
  std::vector<Eigen::Vector2d> x0, x1;
  for (std::size_t i = 0; i < n; ++i) {
    if (!st[i]) continue;
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
  for (std::size_t k = 0; k < idx.size(); ++k) {
    if (!inl[k]) continue;
    Track tr = tracks_[idx[k]];
    tr.uv0 = cur[idx[k]];
    tr.xy0 = x1[k];
    ++tr.age;
    kept.push_back(tr);
  }
  tracks_ = std::move(kept);
  stats_.ransac_inliers = static_cast<int>(tracks_.size());
}

void KltTracker::detect_new(const cv::Mat& img) {
  const int wanted = p_.num_features - static_cast<int>(tracks_.size());
  // Small deficits wait until they add up: each detection pass runs FAST in every cell below
  // its quota, which costs about as much for one feature as for ten.
  if (wanted <= 0 || wanted < std::min(p_.detect_min_missing, p_.num_features)) return;
  std::vector<cv::Point2f> existing;
  existing.reserve(tracks_.size());
  for (const auto& t : tracks_) existing.push_back(t.uv0);
  const CameraModel& cam = *cams_[0];
  for (const auto& p : detector_.detect(img, existing, wanted)) {
    Track tr;
    if (!cam.undistort({p.x, p.y}, &tr.xy0)) continue;
    if (p_.template_refinement) {
      tr.birth = refiner_.make_template(img, p);
      if (!tr.birth) continue;  // at the border or an edge: not worth a track
    }
    tr.id = next_id_++;
    tr.uv0 = p;
    tracks_.push_back(tr);
    ++stats_.detected;
  }
}

void KltTracker::match_stereo(const std::vector<cv::Mat>& pyr0, const std::vector<cv::Mat>& pyr1,
                              const cv::Mat& right_img) {
  const std::size_t n = tracks_.size();
  std::vector<cv::Point2f> uv0(n), guess(n);
  std::vector<std::uint8_t> close(n, 0);
  std::vector<Eigen::Vector2d> xy0(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Track& t = tracks_[i];
    uv0[i] = t.uv0;
    xy0[i] = t.xy0;
    // Last frame's disparity is the best guess; new or unmatched tracks start at infinity.
    guess[i] = t.has_right ? t.uv0 + t.right_offset : stereo_->infinity_guess(t.xy0);
    close[i] = t.has_right ? 1 : 0;
  }
  std::vector<cv::Point2f> uv1;
  std::vector<Eigen::Vector2d> xy1;
  std::vector<std::uint8_t> ok;
  stereo_->match(pyr0, pyr1, uv0, xy0, guess, &close, &uv1, &xy1, &ok);
  stats_.stereo_matched = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Track& t = tracks_[i];
    t.has_right = ok[i] != 0;
    // The epipolar check cannot see a match that slid along the epipolar line: align the
    // birth patch (in its current shape) on the right image too; it must correlate, stay
    // close to the KLT match and on the epipolar line.
    if (t.has_right && p_.template_refinement && t.birth) {
      PatchWarp w = t.warp;
      const RefineResult r = refiner_.refine(right_img, *t.birth, uv1[i], &w);
      Eigen::Vector2d x1;
      t.has_right = r.ok && r.zncc >= p_.template_min_zncc &&
                    cv::norm(r.uv - uv1[i]) <= p_.template_max_shift_px &&
                    cams_[1]->undistort({r.uv.x, r.uv.y}, &x1) &&
                    stereo_->epipolar_distance_px(t.xy0, x1) <= p_.stereo_epipolar_px;
      if (t.has_right) {
        uv1[i] = r.uv;
        xy1[i] = x1;
      }
    }
    if (t.has_right) {
      t.uv1 = uv1[i];
      t.right_offset = t.uv1 - t.uv0;
      t.xy1 = xy1[i];
      ++stats_.stereo_matched;
    }
  }
}

FeatureFrame KltTracker::make_output(TimeNs t_ns) const {
  FeatureFrame out;
  out.t_ns = t_ns;
  out.observations.reserve(tracks_.size() * 2);
  const int id0 = cams_[0]->calib().cam_id;
  for (const auto& t : tracks_) {
    out.observations.push_back({id0, t.id, {t.uv0.x, t.uv0.y}, t.xy0, true});
  }
  if (stereo_) {
    const int id1 = cams_[1]->calib().cam_id;
    for (const auto& t : tracks_) {
      if (t.has_right) out.observations.push_back({id1, t.id, {t.uv1.x, t.uv1.y}, t.xy1, true});
    }
  }
  return out;
}

FeatureFrame KltTracker::process(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right) {
  using Clock = std::chrono::steady_clock;
  const auto ms_since = [](Clock::time_point a) {
    return std::chrono::duration<double, std::milli>(Clock::now() - a).count();
  };
  const auto t_start = Clock::now();
  stats_ = TrackerStats{};
  const bool stereo = stereo_ && !right.empty();
  // Left pyramid with derivatives: it is the source image of the stereo match now and of the
  // temporal match next frame. The right one needs derivatives only for the backward check.
  const cv::Mat img0 = prepare(left, *cams_[0]);
  pyramid(img0, true, &cur_pyr_);
  cv::Mat img1;
  if (stereo) {
    img1 = prepare(right, *cams_[1]);
    pyramid(img1, p_.stereo_fb_check_px > 0.0, &right_pyr_);
  }
  stats_.ms_pyramid = ms_since(t_start);

  auto t = Clock::now();
  track_temporal(img0, cur_pyr_, t_ns);
  stats_.ms_temporal = ms_since(t);
  t = Clock::now();
  detect_new(img0);
  stats_.ms_detect = ms_since(t);
  t = Clock::now();
  if (stereo) {
    match_stereo(cur_pyr_, right_pyr_, img1);
  } else {
    for (auto& tr : tracks_) tr.has_right = false;
  }
  stats_.ms_stereo = ms_since(t);

  std::swap(prev_pyr_, cur_pyr_);
  prev_t_ = t_ns;
  const double shift_ns = cams_[0]->calib().timeshift_cam_imu_s * 1e9;
  gyro_.prune_before(t_ns + static_cast<TimeNs>(std::llround(shift_ns)) - 100'000'000);
  stats_.ms_total =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  return make_output(t_ns);
}

}  // namespace vid
