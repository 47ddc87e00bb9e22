#pragma once
/// @file texture.h
/// @brief Procedural surface textures: a "dead leaves" mix of hard-edged random shapes
/// (rectangles, rotated quads, triangles, ellipses) at several scales plus multi-octave
/// smooth value noise. No periodic structure, many corners, smooth gradients.

#include <opencv2/core.hpp>

#include <cstdint>

namespace vid::sim {

/// @brief Look of one surface texture.
struct TextureStyle {
  double mean_level = 128.0;   ///< average gray level of the shapes [0, 255]
  double level_spread = 100.0; ///< shapes' gray levels are uniform in mean +- spread
  double shape_density = 1.0;  ///< multiplies the per-scale area coverage of shapes
  double noise_amplitude = 22.0;  ///< total amplitude of the smooth noise octaves [gray]
};

/// @brief Make a texture of `size_m_u` x `size_m_v` metres at `texels_per_m` (CV_8UC1,
/// cols along u, rows along v; texel (i, j) covers [j, j+1) x [i, i+1) / texels_per_m).
/// Deterministic for a given seed.
cv::Mat make_surface_texture(double size_m_u, double size_m_v, double texels_per_m,
                             std::uint64_t seed, const TextureStyle& style);

}  // namespace vid::sim
