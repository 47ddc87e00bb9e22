#include "frontend/track_drawing.h"

#include <opencv2/imgproc.hpp>
#include <unordered_set>

namespace vid {

void TrackDrawer::update(const std::vector<Track>& tracks) {
  std::unordered_set<std::uint64_t> live;
  for (const auto& t : tracks) {
    live.insert(t.id);
    auto& trail = trails_[t.id];
    trail.push_back(t.uv0);
    while (trail.size() > trail_length_) trail.pop_front();
  }
  for (auto it = trails_.begin(); it != trails_.end();) {
    it = live.count(it->first) ? std::next(it) : trails_.erase(it);
  }
}

cv::Mat TrackDrawer::draw(const cv::Mat& left, const cv::Mat& right,
                          const std::vector<Track>& tracks, const std::string& caption) const {
  auto to_bgr = [](const cv::Mat& g) {
    cv::Mat c;
    if (g.channels() == 1) cv::cvtColor(g, c, cv::COLOR_GRAY2BGR);
    else c = g.clone();
    return c;
  };
  const cv::Mat l = to_bgr(left);
  cv::Mat canvas;
  if (right.empty()) {
    canvas = l;
  } else {
    cv::hconcat(l, to_bgr(right), canvas);
  }
  const float off = static_cast<float>(left.cols);
  auto color_of = [](int age) {
    if (age == 0) return cv::Scalar(0, 0, 255);
    if (age < 5) return cv::Scalar(0, 255, 255);
    return cv::Scalar(0, 255, 0);
  };
  for (const auto& t : tracks) {
    const cv::Scalar col = color_of(t.age);
    auto it = trails_.find(t.id);
    if (it != trails_.end()) {
      for (std::size_t k = 1; k < it->second.size(); ++k) {
        cv::line(canvas, it->second[k - 1], it->second[k], col, 1, cv::LINE_AA);
      }
    }
    cv::circle(canvas, t.uv0, 3, col, 1, cv::LINE_AA);
    if (t.has_right) {
      const cv::Point2f r = t.uv1 + cv::Point2f(off, 0.f);
      cv::circle(canvas, r, 3, col, 1, cv::LINE_AA);
      cv::line(canvas, t.uv0 + cv::Point2f(off, 0.f), r, cv::Scalar(255, 128, 0), 1, cv::LINE_AA);
    }
  }
  cv::putText(canvas, caption, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 3,
              cv::LINE_AA);
  cv::putText(canvas, caption, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(255, 255, 255),
              1, cv::LINE_AA);
  return canvas;
}

}  // namespace vid
