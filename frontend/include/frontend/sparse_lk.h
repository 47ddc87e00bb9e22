#pragma once
/// @file sparse_lk.h
/// @brief Pyramidal Lucas-Kanade for sparse points (translation only; Bouguet's coarse-to-fine
/// scheme), the frontend's one KLT.
///
/// Written here rather than calling cv::calcOpticalFlowPyrLK because that one needs the Scharr
/// derivative images of every pyramid level of the source image (cv::buildOpticalFlowPyramid
/// with derivatives, or computed inside each call): 0.23 ms per 640x480 image whether it tracks
/// one point or 150. With direct birth-patch alignment only a few points per frame need KLT;
/// here the gradients come from each point's own window, so only the plain image pyramids are
/// built (0.09 ms per image).

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace vid {

/// @brief Settings of one sparse_lk call.
struct LkParams {
  int window = 15;           ///< window side [px], odd
  int levels = 2;            ///< pyramid levels above the base image used (coarsest first)
  int max_iterations = 30;   ///< Gauss-Newton iterations per level
  double epsilon = 0.01;     ///< stop when the step is shorter [px of that level]
  /// Minimum eigenvalue of the window's gradient matrix per pixel, on the scale of
  /// cv::calcOpticalFlowPyrLK's minEigThreshold (its Scharr gradients are 32x the central
  /// differences used here, and it divides by 2^20): below it, the point fails at the base
  /// level and the coarser levels keep their guess.
  double min_eigen = 1e-4;
};

/// @brief Plain image pyramid for sparse_lk: levels + 1 images, each padded by `window` pixels
/// (cv::buildOpticalFlowPyramid without derivatives) so windows may reach past the image edge.
/// Reuses pyr's buffers.
void build_lk_pyramid(const cv::Mat& img, int window, int levels, std::vector<cv::Mat>* pyr);

/// @brief Tracks from[i] (pixel of the base image of pyr_from) into pyr_to, starting at
/// (*to)[i]; results in *to. ok[i] = 0 where the window left the padded image, the gradient
/// matrix was too weak (see LkParams::min_eigen) or the result is not finite.
void sparse_lk(const std::vector<cv::Mat>& pyr_from, const std::vector<cv::Mat>& pyr_to,
               const std::vector<cv::Point2f>& from, std::vector<cv::Point2f>* to,
               std::vector<std::uint8_t>* ok, const LkParams& p);

}  // namespace vid
