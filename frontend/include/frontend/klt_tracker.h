#pragma once
/// @file klt_tracker.h
/// @brief Mono / stereo KLT feature tracker: grid FAST detection, gyro-aided pyramidal
/// Lucas-Kanade between frames, forward-backward and RANSAC outlier rejection, left -> right
/// stereo matching. Emits FeatureFrame observations with stable ids.
///
/// With direct_alignment (default) a track whose position is well predicted (gyro rotation
/// plus last frame's residual motion; stereo: last disparity) is tracked by aligning its birth
/// patch alone; KLT and its image pyramids run only for new tracks and failed alignments.

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
#include "types/calibration.h"
#include "types/measurements.h"

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
  cv::Point2f flow;                 ///< last frame's motion beyond the gyro rotation [px]
  bool has_flow = false;            ///< flow is known (tracked in at least one frame)
  int stereo_wait = 0;              ///< frames to skip before the next stereo attempt
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
  int direct_aligned = 0;  ///< temporal: tracked by the birth-patch alignment alone
  int stereo_direct = 0;   ///< stereo: matched by the birth-patch alignment alone
  int klt_points = 0;      ///< points that went through pyramidal KLT (temporal + stereo)
  int pyramids = 0;        ///< image pyramids built in this frame (0-3)
  bool gyro_used = false;  ///< prediction came from the gyro
  double ms_total = 0.0;   ///< wall time of process() [ms]
  double ms_pyramid = 0.0;   ///< pre-processing and every pyramid built
  double ms_temporal = 0.0;  ///< temporal alignment / KLT and RANSAC (its pyramids excluded)
  double ms_detect = 0.0;    ///< detection of new features
  double ms_stereo = 0.0;    ///< stereo matching (its pyramids excluded)
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
  /// Pyramids of this frame's left / right image and of the previous left image, built on
  /// first use (build_lk_pyramid).
  const std::vector<cv::Mat>& left_pyramid();
  const std::vector<cv::Mat>& right_pyramid();
  const std::vector<cv::Mat>& prev_pyramid();
  void build_pyramid(const cv::Mat& img, std::vector<cv::Mat>* pyr);
  /// Gyro-rotated positions of the tracks in this frame (rotation only; `rot` = uv0 without gyro).
  void predict_rotation(TimeNs t_ns, std::vector<cv::Point2f>* rot,
                        std::optional<Eigen::Matrix3d>* R_prev_cur);
  /// rot + each track's last residual motion (its nearest tracked neighbour's for new tracks).
  std::vector<cv::Point2f> predict_flow(const std::vector<cv::Point2f>& rot) const;
  void track_temporal(TimeNs t_ns);
  /// Pyramidal KLT from prev to cur for the tracks with todo[i], then the birth-patch check;
  /// sets ok[i] and cur[i] for them.
  void klt_temporal(const std::vector<std::uint8_t>& todo, std::vector<cv::Point2f>* cur,
                    std::vector<std::uint8_t>* ok);
  /// Aligns the birth patch of each candidate with todo[i] && ok[i]; clears ok[i] for tracks
  /// that fail.
  void refine_to_birth(const std::vector<std::uint8_t>& todo, std::vector<cv::Point2f>* cur,
                       std::vector<std::uint8_t>* ok);
  /// Temporal RANSAC over the tracked candidates; keeps the inliers in tracks_.
  void keep_inliers(const std::vector<cv::Point2f>& rot, const std::vector<cv::Point2f>& cur,
                    const std::vector<std::uint8_t>& ok,
                    const std::optional<Eigen::Matrix3d>& R_prev_cur, TimeNs t_ns);
  void detect_new(const cv::Mat& img);
  void match_stereo();
  /// Stereo KLT (and the birth-patch check on the right image) for the tracks with todo[i].
  void klt_stereo(const std::vector<std::uint8_t>& todo);
  FeatureFrame make_output(TimeNs t_ns) const;
  bool direct() const { return p_.direct_alignment && p_.template_refinement; }

  FrontendParams p_;
  std::vector<std::unique_ptr<CameraModel>> cams_;
  GridDetector detector_;
  std::unique_ptr<StereoMatcher> stereo_;
  GyroIntegrator gyro_;
  cv::Ptr<cv::CLAHE> clahe_;
  PatchRefiner refiner_;
  cv::Mat img0_, img1_;  ///< this frame's prepared left / right image
  cv::Mat prev_img_;     ///< last frame's prepared left image (kept when its pyramid was not built)
  std::vector<cv::Mat> prev_pyr_, cur_pyr_, right_pyr_;
  bool prev_pyr_ok_ = false, cur_pyr_ok_ = false, right_pyr_ok_ = false;
  std::optional<TimeNs> prev_t_;
  std::vector<Track> tracks_;
  std::uint64_t next_id_ = 1;
  TrackerStats stats_;
};

}  // namespace vid
