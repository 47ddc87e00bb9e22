#include "frontend/klt_tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "frontend/sparse_lk.h"

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

void KltTracker::build_pyramid(const cv::Mat& img, std::vector<cv::Mat>* pyr) {
  const auto t0 = std::chrono::steady_clock::now();
  const int levels = stereo_ ? std::max(p_.lk_levels, p_.stereo_lk_levels) : p_.lk_levels;
  build_lk_pyramid(img, p_.lk_window, levels, pyr);
  ++stats_.pyramids;
  stats_.ms_pyramid +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

const std::vector<cv::Mat>& KltTracker::left_pyramid() {
  if (!cur_pyr_ok_) build_pyramid(img0_, &cur_pyr_);
  cur_pyr_ok_ = true;
  return cur_pyr_;
}

const std::vector<cv::Mat>& KltTracker::right_pyramid() {
  if (!right_pyr_ok_) build_pyramid(img1_, &right_pyr_);
  right_pyr_ok_ = true;
  return right_pyr_;
}

const std::vector<cv::Mat>& KltTracker::prev_pyramid() {
  if (!prev_pyr_ok_) build_pyramid(prev_img_, &prev_pyr_);
  prev_pyr_ok_ = true;
  return prev_pyr_;
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
  img0_ = prepare(left, *cams_[0]);
  img1_ = stereo ? prepare(right, *cams_[1]) : cv::Mat();
  cur_pyr_ok_ = right_pyr_ok_ = false;
  stats_.ms_pyramid = ms_since(t_start);
  if (!direct()) {  // every point goes through KLT: the pyramids up front
    left_pyramid();
    if (stereo) right_pyramid();
  }
  // Stage times exclude the pyramids built inside them (those count in ms_pyramid).
  const auto stage = [&](auto&& run) {
    const auto t = Clock::now();
    const double pyramid_before = stats_.ms_pyramid;
    run();
    return ms_since(t) - (stats_.ms_pyramid - pyramid_before);
  };
  stats_.ms_temporal = stage([&] { track_temporal(t_ns); });
  stats_.ms_detect = stage([&] { detect_new(img0_); });
  stats_.ms_stereo = stage([&] {
    if (stereo) {
      match_stereo();
    } else {
      for (auto& tr : tracks_) tr.has_right = false;
    }
  });

  // Next frame's temporal KLT starts from this left image: its pyramid if one was built, else
  // the image itself (copied when it is the caller's buffer, which the caller may reuse).
  if (cur_pyr_ok_) {
    std::swap(prev_pyr_, cur_pyr_);
    prev_pyr_ok_ = true;
  } else {
    prev_pyr_ok_ = false;
    if (img0_.data == left.data) {
      img0_.copyTo(prev_img_);
    } else {
      prev_img_ = img0_;
    }
  }
  prev_t_ = t_ns;
  const double shift_ns = cams_[0]->calib().timeshift_cam_imu_s * 1e9;
  gyro_.prune_before(t_ns + static_cast<TimeNs>(std::llround(shift_ns)) - 100'000'000);
  stats_.ms_total = ms_since(t_start);
  return make_output(t_ns);
}

}  // namespace vid
