#include "frontend/image_noise.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace vid {

double estimate_noise_sigma(const cv::Mat& gray, int block, int stride) {
  CV_Assert(gray.type() == CV_8UC1);
  block = std::max(4, block);
  stride = std::max(1, stride);
  std::vector<double> block_sigma;
  for (int by = 1; by + block <= gray.rows - 1; by += block) {
    for (int bx = 1; bx + block <= gray.cols - 1; bx += block) {
      long sum_abs = 0, sum_level = 0, n = 0;
      for (int y = by; y < by + block; y += stride) {
        const std::uint8_t* a = gray.ptr<std::uint8_t>(y - 1);
        const std::uint8_t* b = gray.ptr<std::uint8_t>(y);
        const std::uint8_t* c = gray.ptr<std::uint8_t>(y + 1);
        for (int x = bx; x < bx + block; x += stride) {
          const int r = (a[x - 1] - 2 * a[x] + a[x + 1]) - 2 * (b[x - 1] - 2 * b[x] + b[x + 1]) +
                        (c[x - 1] - 2 * c[x] + c[x + 1]);
          sum_abs += std::abs(r);
          sum_level += b[x];
          ++n;
        }
      }
      // Clipped blocks (black or white) hold no noise: they would read as the flattest.
      const double level = static_cast<double>(sum_level) / static_cast<double>(n);
      if (level < 16.0 || level > 239.0) continue;
      // E|N*I| = 6 s sqrt(2 / pi) for Gaussian noise of sigma s.
      block_sigma.push_back(static_cast<double>(sum_abs) / static_cast<double>(n) / 4.7873);
    }
  }
  if (block_sigma.empty()) return 0.0;
  const auto q = block_sigma.begin() + static_cast<std::ptrdiff_t>(block_sigma.size() / 10);
  std::nth_element(block_sigma.begin(), q, block_sigma.end());
  return *q;
}

}  // namespace vid
