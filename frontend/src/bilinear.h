#pragma once
// Bilinear sampling of a translated square grid, shared by the birth-patch alignment
// (patch_refiner.cpp) and our sparse LK (sparse_lk.cpp). Private to the frontend library.
#include <cstddef>
#include <cstdint>

namespace vid {

/// @brief Bilinear samples of the n x n pixel grid whose first sample lies at fraction
/// (fx, fy) in [0, 1) right of and below the 8-bit pixel `p`: one set of weights for every
/// sample, so the compiler vectorizes along the rows. Reads n + 1 rows and columns from p;
/// the caller has checked they exist.
inline void sample_translated(const std::uint8_t* p, std::ptrdiff_t step, int n, float fx, float fy,
                              float* out) {
  const float w00 = (1.f - fx) * (1.f - fy), w01 = fx * (1.f - fy);
  const float w10 = (1.f - fx) * fy, w11 = fx * fy;
  for (int r = 0; r < n; ++r, p += step) {
    const std::uint8_t* q = p + step;
    for (int k = 0; k < n; ++k) *out++ = w00 * p[k] + w01 * p[k + 1] + w10 * q[k] + w11 * q[k + 1];
  }
}

}  // namespace vid
