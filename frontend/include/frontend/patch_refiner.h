#pragma once
/// @file patch_refiner.h
/// @brief Drift-free refinement of a tracked point against the patch it was born on:
/// inverse-compositional affine Lucas-Kanade (Baker & Matthews) with gain/bias normalization,
/// and a zero-mean normalized cross-correlation (ZNCC) score of the final alignment.
///
/// Frame-to-frame KLT accumulates a small error every frame (a random walk plus a bias from
/// the patch changing shape). Aligning the birth template to the current image, starting from
/// the KLT position and the previous affine shape, removes that accumulation; the ZNCC of the
/// aligned patch exposes tracks whose appearance stopped matching the birth patch (occlusion
/// edges, a foreground edge sliding over the background).

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace vid {

/// @brief Birth patch of one track with the precomputed inverse-compositional terms.
struct PatchTemplate {
  int half = 0;                  ///< patch is (2 half + 1)^2 pixels
  std::vector<float> value;      ///< zero-mean intensities, row-major
  std::vector<float> gx, gy;     ///< template gradients
  float norm = 0.f;              ///< sqrt(sum value^2)
  float prior = 0.f;             ///< weight of the prior on the per-frame change of the shape
  Eigen::Matrix<float, 6, 6> H_inv;  ///< inverse of (Gauss-Newton Hessian + shape prior)
};

/// @brief Current affine shape of a track: pixel = A * (template offset) + centre.
struct PatchWarp {
  Eigen::Matrix2f A = Eigen::Matrix2f::Identity();
};

/// @brief Result of one refinement.
struct RefineResult {
  bool ok = false;          ///< converged inside the image with a sane warp
  cv::Point2f uv;           ///< refined centre
  float zncc = 0.f;         ///< ZNCC of the aligned patch with the template (1 = identical)
  int iterations = 0;
};

/// @brief Builds birth templates and aligns them to later images (8-bit gray, level 0).
class PatchRefiner {
 public:
  /// @param half            patch half size [px] (patch side 2 half + 1)
  /// @param max_iterations  Gauss-Newton iterations per refinement
  /// @param epsilon_px      stop when the centre moves less than this [px]
  /// @param shape_prior     weight (relative to the mean affine Hessian diagonal) of a prior
  ///                        that keeps the affine shape close to the previous frame's: the
  ///                        shape follows perspective change over several frames but cannot
  ///                        wander along poorly observed directions (edges, flat sides)
  PatchRefiner(int half, int max_iterations, double epsilon_px, double shape_prior = 1.0);

  /// @brief Template of the patch centred at uv; nullptr when too close to the border or
  /// texture-less (singular Hessian).
  std::shared_ptr<const PatchTemplate> make_template(const cv::Mat& img, cv::Point2f uv) const;

  /// @brief Align `t` to `img` starting from centre uv and shape `warp` (updated on success).
  RefineResult refine(const cv::Mat& img, const PatchTemplate& t, cv::Point2f uv,
                      PatchWarp* warp) const;

  /// @brief ZNCC of `t` with the patch of `img` at uv under shape `warp` (no alignment);
  /// -1 if the patch leaves the image.
  float zncc(const cv::Mat& img, const PatchTemplate& t, cv::Point2f uv,
             const PatchWarp& warp) const;

  /// @brief Whether the patch at uv under shape `warp` lies inside an image of `size` (as
  /// refine() needs to sample it).
  bool fits(cv::Size size, cv::Point2f uv, const PatchWarp& warp) const;

  int half() const { return half_; }

 private:
  /// Samples the warped patch into buf (bilinear); false if any sample leaves the image.
  bool sample(const cv::Mat& img, const Eigen::Matrix2f& A, cv::Point2f c, float* buf) const;

  int half_;
  int max_iterations_;
  float epsilon_px_;
  double shape_prior_;
  std::vector<float> xs_, ys_;  ///< template offsets of each patch pixel
};

}  // namespace vid
