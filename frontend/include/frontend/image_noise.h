#pragma once
/// @file image_noise.h
/// @brief Sensor noise of a gray image, estimated from the image itself.

#include <opencv2/core.hpp>

namespace vid {

/// @brief Standard deviation of the pixel noise of an 8-bit gray image [gray levels],
/// measured where the image is flattest (Immerkaer 1996, "Fast noise variance estimation",
/// per block).
///
/// The mask N = [1 -2 1; -2 4 -2; 1 -2 1] (the product of two second differences) cancels
/// every image that is linear along x or along y, so smooth shading gives ~0 while white noise
/// of sigma s gives E|N*I| = 6 s sqrt(2 / pi). Texture adds to |N*I|, and the paper's mean over
/// the whole image reads it as noise (rendered rooms: 3.1 for 2 gray levels); so the image is
/// cut into block x block squares, each gives its own sigma, and the 10th percentile of the
/// blocks is returned: any plain wall, floor or sky in view gives the noise (within ~6 %: the
/// spread of a block's mean). A fully textured image still reads high. Blocks whose mean level
/// is clipped (< 16 or > 239) are skipped. Samples every `stride`-th pixel of each block.
/// Returns 0 when no block fits.
double estimate_noise_sigma(const cv::Mat& gray, int block = 32, int stride = 2);

}  // namespace vid
