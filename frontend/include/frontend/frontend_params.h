#pragma once
/// @file frontend_params.h
/// @brief Settings of the KLT frontend (plain data with defaults; loaded from YAML by the app
/// layer, see frontend/include/frontend/frontend_params_yaml.h).

namespace vid {

/// @brief How temporal outliers are rejected.
enum class RansacMode {
  kNone,         ///< no temporal RANSAC
  kFundamental,  ///< fundamental matrix on undistorted normalized points (8-point RANSAC)
  kTwoPoint,     ///< translation-only epipolar model given the gyro rotation (2-point RANSAC)
};

/// @brief Image pre-processing before detection and tracking.
enum class Equalization { kNone, kHistogram, kClahe };

/// @brief All frontend settings; defaults suit 640x480 stereo at 20-30 Hz.
struct FrontendParams {
  // --- detection ---
  int num_features = 150;       ///< features requested per (left) image
  int grid_cols = 8;            ///< detection grid columns
  int grid_rows = 6;            ///< detection grid rows
  int fast_threshold = 20;      ///< FAST intensity threshold
  int fast_threshold_min = 7;   ///< retry threshold for cells with no corner at fast_threshold
  /// Both FAST thresholds are raised to at least this many times the image's noise sigma
  /// (estimate_noise_sigma, once per detection call); 0 = fixed thresholds (default). Pure
  /// noise gives FAST ~2.5 corners per 80x80 cell at 3 sigma, ~50 at 2 sigma and hundreds
  /// below: a dark, high-gain camera (dark_room: sigma ~11 levels) at the fixed 20 / 7 takes
  /// mostly noise corners. Off by default: at 3 it also raises the retry threshold of
  /// moderately noisy images with plain surfaces (vid17_hard: 7 -> 8), which cost 22 % ATE
  /// there (docs/notes/frontend.md, "FAST thresholds and image noise").
  double fast_noise_factor = 0.0;
  double min_distance_px = 12;  ///< minimum distance between features [px]
  int border_px = 8;            ///< features closer to the image edge are dropped [px]
  int detect_cell_retry_frames = 4;  ///< a cell searched in vain (or whose new features all died at once) is skipped this many frames
  int detect_min_missing = 8;   ///< detect only when at least this many features are missing

  // --- pre-processing ---
  /// Significant bits of 16-bit images (a 12-bit camera right-aligned in 16-bit PNGs: 12);
  /// 0 = auto: found once per camera stream from sample images (vid::detect_bit_depth) and kept
  /// for the whole stream. 16-bit pixels are divided by 2^(bits - 8); 8-bit images ignore it.
  int image_bit_depth = 0;
  Equalization equalization = Equalization::kNone;  ///< contrast equalization before detection and tracking
  double clahe_clip_limit = 2.0;  ///< CLAHE contrast limit (equalization: clahe)
  int clahe_tile = 8;           ///< CLAHE tiles per side

  // --- pyramidal Lucas-Kanade ---
  int lk_levels = 2;            ///< pyramid levels above the base image
  int lk_window = 15;           ///< window side [px]
  int lk_max_iterations = 30;   ///< per level, for points without a good prediction
  double lk_epsilon = 0.01;     ///< stop when the update is below this [px]
  /// Same for points that start at a good prediction (gyro-predicted temporal tracks, stereo
  /// tracks at last frame's disparity): the birth-patch alignment refines the result, so a
  /// coarser stop costs no accuracy (vid17_like/fast_yaw scores unchanged) and saves ~10 %.
  int lk_predicted_max_iterations = 10;
  double lk_predicted_epsilon = 0.03;  ///< [px]
  double lk_min_eigen = 1e-4;   ///< cv::calcOpticalFlowPyrLK minEigThreshold
  double fb_check_px = 0.0;     ///< forward-backward check [px]; <= 0 disables (the birth-template
                                ///< check below is stricter and cheaper)

  // --- refinement against the birth patch (removes frame-to-frame drift) ---
  bool template_refinement = true;  ///< align each track's birth patch (affine IC-LK) every frame
  int template_half = 7;            ///< birth patch half size [px] (15x15)
  int template_iterations = 6;      ///< Gauss-Newton iterations (at most)
  double template_epsilon_px = 0.05;  ///< stop after a step moving the centre less [px]
  double template_min_zncc = 0.9;   ///< tracks whose aligned patch correlates less are dropped
  double template_max_shift_px = 2.0;  ///< drop if the alignment moves the KLT result further
  /// Track by the birth-patch alignment alone where the position is predicted well: a tracked
  /// feature at its gyro-rotated position plus last frame's residual image motion (its own, or
  /// its nearest tracked neighbour's for a new feature), a stereo match at last frame's
  /// disparity. Pyramidal KLT (and its pyramids) only for the rest and for alignments that fail
  /// or move further than template_max_shift_px. Needs template_refinement (ignored without).
  bool direct_alignment = true;

  // --- temporal outlier rejection ---
  RansacMode ransac = RansacMode::kFundamental;  ///< temporal outlier model (two_point: translation given the gyro rotation)
  double ransac_threshold_px = 1.0;  ///< epipolar error threshold (converted with the focal length)
  double ransac_confidence = 0.99;   ///< RANSAC success probability, in (0, 1)
  int ransac_max_iterations = 200;   ///< for the 2-point model

  // --- stereo ---
  bool stereo = true;                ///< match left features into the right image when present
  double stereo_epipolar_px = 1.5;   ///< max distance to the epipolar line [px]
  int stereo_lk_levels = 3;          ///< pyramid levels for left -> right KLT (new features start
                                     ///< at the infinity guess, up to tens of px away)
  int stereo_track_lk_levels = 0;    ///< pyramid levels for tracks matched in the previous frame
                                     ///< (guess: last disparity, which changes by < 1 px/frame;
                                     ///< 0 and 1 scored the same on vid17_like, 0 is 0.2 ms faster)
  double stereo_fb_check_px = 0.0;   ///< right -> left backward check [px]; <= 0 disables (off:
                                     ///< the birth patch is checked on the right image instead)
  /// A track whose stereo match failed waits this many frames before the next attempt: most
  /// such points are outside the right image (near the left image's outer edge) or occluded
  /// in it, and would fail (and cost a KLT pass with its pyramids) every frame.
  int stereo_retry_frames = 4;
  double stereo_max_disparity_px = 200.0;  ///< larger disparities (very near points) are rejected
  double stereo_min_depth_m = 0.1;   ///< triangulated depth must exceed this

  // --- gyro prediction ---
  bool gyro_prediction = true;       ///< predict feature positions from integrated gyro
};

}  // namespace vid
