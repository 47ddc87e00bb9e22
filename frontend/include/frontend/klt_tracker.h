#pragma once
/// @file klt_tracker.h
/// @brief Mono / stereo KLT feature tracker: grid FAST detection, gyro-aided pyramidal
/// Lucas-Kanade between frames, forward-backward and RANSAC outlier rejection, left -> right
/// stereo matching. Emits FeatureFrame observations with stable ids.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "frontend/camera_model.h"
#include "frontend/frontend_params.h"
#include "frontend/grid_detector.h"
#include "frontend/gyro_integrator.h"
#include "frontend/patch_refiner.h"
#include "frontend/stereo_matcher.h"
#include "vio_core/calibration.h"
#include "vio_core/measurements.h"

namespace vid {

/// @brief One live track (left camera, plus its right match when stereo succeeded).
struct Track {
  std::uint64_t id = 0;
  int age = 0;                      ///< frames since detection (0 on the detection frame)
  cv::Point2f uv0;                  ///< left pixel (distorted)
  Eigen::Vector2d xy0;              ///< left undistorted normalized
  bool has_right = false;
  cv::Point2f uv1;                  ///< right pixel (valid if has_right)
  Eigen::Vector2d xy1 = Eigen::Vector2d::Zero();
  cv::Point2f right_offset;         ///< uv1 - uv0 at the last stereo match (next guess)
  std::shared_ptr<const PatchTemplate> birth;  ///< birth patch (null: refinement off)
  PatchWarp warp;                   ///< current affine shape of the birth patch
};

/// @brief What happened in the last processed frame.
struct TrackerStats {
  int previous = 0;        ///< tracks entering the frame
  int klt_tracked = 0;     ///< survived KLT + forward-backward + border + template check
  int template_rejected = 0;  ///< dropped by the birth-template check (low ZNCC, no fit)
  int template_iterations = 0;  ///< Gauss-Newton iterations of all template alignments
  int ransac_inliers = 0;  ///< survived temporal RANSAC (= tracks kept)
  int detected = 0;        ///< new features
  int stereo_matched = 0;  ///< tracks with a right observation
  bool gyro_used = false;  ///< prediction came from the gyro
  double ms_total = 0.0;   ///< wall time of process() [ms]
  double ms_pyramid = 0.0;   ///< pre-processing and pyramids (both images)
  double ms_temporal = 0.0;  ///< temporal KLT, template refinement and RANSAC
  double ms_detect = 0.0;    ///< detection of new features
  double ms_stereo = 0.0;    ///< stereo matching
};

/// @brief The KLT frontend for one camera (mono) or a camera pair (stereo: cams[0] left,
/// cams[1] right).
class KltTracker {
 public:
  /// @throws std::invalid_argument on an empty camera list or bad calibration
  KltTracker(const FrontendParams& params, const std::vector<CameraCalib>& cams);

  /// @brief Feed a gyro sample (IMU time); used for prediction and the 2-point RANSAC.
  void add_imu(const ImuSample& s);

  /// @brief Process one frame (camera time t_ns). `right` may be empty (mono).
  /// Images must be 8-bit (gray, or BGR which is converted).
  /// @throws std::invalid_argument if the image size differs from the calibration
  FeatureFrame process(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right = cv::Mat());

  /// @brief Live tracks after the last process().
  const std::vector<Track>& tracks() const { return tracks_; }
  /// @brief Statistics of the last process().
  const TrackerStats& stats() const { return stats_; }
  /// @brief Camera models (index = position in the calibration list).
  const CameraModel& camera(std::size_t i) const { return *cams_.at(i); }
  const FrontendParams& params() const { return p_; }

 private:
  cv::Mat prepare(const cv::Mat& img, const CameraModel& cam) const;
  void pyramid(const cv::Mat& img, bool derivatives, std::vector<cv::Mat>* pyr) const;
  void track_temporal(const cv::Mat& img, const std::vector<cv::Mat>& pyr, TimeNs t_ns);
  /// Aligns the birth patch of each candidate; clears ok[i] for tracks that fail.
  void refine_to_birth(const cv::Mat& img, std::vector<cv::Point2f>* cur,
                       std::vector<std::uint8_t>* ok);
  void detect_new(const cv::Mat& img);
  void match_stereo(const std::vector<cv::Mat>& pyr0, const std::vector<cv::Mat>& pyr1,
                    const cv::Mat& right_img);
  FeatureFrame make_output(TimeNs t_ns) const;

  FrontendParams p_;
  std::vector<std::unique_ptr<CameraModel>> cams_;
  GridDetector detector_;
  std::unique_ptr<StereoMatcher> stereo_;
  GyroIntegrator gyro_;
  cv::Ptr<cv::CLAHE> clahe_;
  PatchRefiner refiner_;
  std::vector<cv::Mat> prev_pyr_, cur_pyr_, right_pyr_;
  std::optional<TimeNs> prev_t_;
  std::vector<Track> tracks_;
  std::uint64_t next_id_ = 1;
  TrackerStats stats_;
};

}  // namespace vid
