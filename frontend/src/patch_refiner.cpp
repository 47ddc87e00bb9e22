#include "frontend/patch_refiner.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <algorithm>
#include <cstdint>
#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

#include "bilinear.h"

namespace vid {
namespace {

/// True if the four corners of the (2 h + 1)^2 grid mapped by A around c lie inside the image
/// (then every sample does: the map is affine); *corner_y_max gets the lowest corner's row.
bool corners_inside(cv::Size size, int h, const Eigen::Matrix2f& A, cv::Point2f c,
                    float* corner_y_max = nullptr) {
  const float hf = static_cast<float>(h);
  const float max_x = static_cast<float>(size.width - 1), max_y = static_cast<float>(size.height - 1);
  float y_max = 0.f;
  for (int sy = -1; sy <= 1; sy += 2) {
    for (int sx = -1; sx <= 1; sx += 2) {
      const float x = A(0, 0) * sx * hf + A(0, 1) * sy * hf + c.x;
      const float y = A(1, 0) * sx * hf + A(1, 1) * sy * hf + c.y;
      if (!(x >= 0.f && y >= 0.f && x < max_x && y < max_y)) return false;
      y_max = std::max(y_max, y);
    }
  }
  if (corner_y_max != nullptr) *corner_y_max = y_max;
  return true;
}

/// Bilinear samples of a (2 h + 1)^2 grid mapped by A around c; false if any leaves the image.
/// xs, ys: the grid offsets (row-major), used on the affine path; may be null when A is the
/// identity (template creation).
bool sample_grid(const cv::Mat& img, int h, const Eigen::Matrix2f& A, cv::Point2f c, float* out,
                 const float* xs = nullptr, const float* ys = nullptr) {
  const int n = 2 * h + 1;
  const float max_y = static_cast<float>(img.rows - 1);
  float corner_y_max = 0.f;
  if (!corners_inside(img.size(), h, A, c, &corner_y_max)) return false;
  const std::size_t step = img.step[0];
  const std::uint8_t* base = img.ptr<std::uint8_t>(0);
  const float dev = (A - Eigen::Matrix2f::Identity()).cwiseAbs().maxCoeff() * static_cast<float>(h);
  if (dev < 0.005f || xs == nullptr || ys == nullptr) {
    if (dev >= 0.005f) return false;  // affine map without offsets: a caller bug
    // (Nearly) a pure translation: one set of bilinear weights for every sample.
    const float x = c.x - static_cast<float>(h), y = c.y - static_cast<float>(h);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);  // x, y >= 0: truncation floors
    sample_translated(base + static_cast<std::size_t>(y0) * step + x0, static_cast<std::ptrdiff_t>(step), n,
                      x - static_cast<float>(x0), y - static_cast<float>(y0), out);
    return true;
  }
  const int N = n * n;
  int i = 0;
#if defined(__AVX2__) && defined(__FMA__)
  // Eight samples at a time: one 32-bit gather per image row fetches both horizontal
  // neighbours (bytes 0 and 1). The gather reads two bytes past the right neighbour, so the
  // lower row must not be the image's last one; the offsets fit int32 for any sane image.
  if (corner_y_max < max_y - 1.f && step * static_cast<std::size_t>(img.rows) < (1u << 30)) {
    const __m256 a00 = _mm256_set1_ps(A(0, 0)), a01 = _mm256_set1_ps(A(0, 1));
    const __m256 a10 = _mm256_set1_ps(A(1, 0)), a11 = _mm256_set1_ps(A(1, 1));
    const __m256 cx = _mm256_set1_ps(c.x), cy = _mm256_set1_ps(c.y);
    const __m256i vstep = _mm256_set1_epi32(static_cast<int>(step));
    const __m256i low = _mm256_set1_epi32(0xFF);
    const int* src = reinterpret_cast<const int*>(base);
    for (; i + 8 <= N; i += 8) {
      const __m256 ox = _mm256_loadu_ps(xs + i), oy = _mm256_loadu_ps(ys + i);
      const __m256 x = _mm256_fmadd_ps(a00, ox, _mm256_fmadd_ps(a01, oy, cx));
      const __m256 y = _mm256_fmadd_ps(a10, ox, _mm256_fmadd_ps(a11, oy, cy));
      const __m256i xi = _mm256_cvttps_epi32(x), yi = _mm256_cvttps_epi32(y);
      const __m256 fx = _mm256_sub_ps(x, _mm256_cvtepi32_ps(xi));
      const __m256 fy = _mm256_sub_ps(y, _mm256_cvtepi32_ps(yi));
      const __m256i off = _mm256_add_epi32(_mm256_mullo_epi32(yi, vstep), xi);
      const __m256i g0 = _mm256_i32gather_epi32(src, off, 1);
      const __m256i g1 = _mm256_i32gather_epi32(src, _mm256_add_epi32(off, vstep), 1);
      const __m256 p00 = _mm256_cvtepi32_ps(_mm256_and_si256(g0, low));
      const __m256 p01 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(g0, 8), low));
      const __m256 p10 = _mm256_cvtepi32_ps(_mm256_and_si256(g1, low));
      const __m256 p11 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(g1, 8), low));
      const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(p01, p00), p00);
      const __m256 bot = _mm256_fmadd_ps(fx, _mm256_sub_ps(p11, p10), p10);
      _mm256_storeu_ps(out + i, _mm256_fmadd_ps(fy, _mm256_sub_ps(bot, top), top));
    }
  }
#endif
  for (; i < N; ++i) {
    const float x = A(0, 0) * xs[i] + A(0, 1) * ys[i] + c.x;
    const float y = A(1, 0) * xs[i] + A(1, 1) * ys[i] + c.y;
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
    const std::uint8_t* p = base + static_cast<std::size_t>(y0) * step + x0;
    const float top = p[0] + fx * (static_cast<float>(p[1]) - p[0]);
    const float bot = p[step] + fx * (static_cast<float>(p[step + 1]) - p[step]);
    out[i] = top + fy * (bot - top);
  }
  return true;
}

}  // namespace

PatchRefiner::PatchRefiner(int half, int max_iterations, double epsilon_px, double shape_prior)
    : half_(half),
      max_iterations_(max_iterations),
      epsilon_px_(static_cast<float>(epsilon_px)),
      shape_prior_(shape_prior) {
  const int n = 2 * half_ + 1;
  for (int r = 0; r < n; ++r) {
    for (int k = 0; k < n; ++k) {
      xs_.push_back(static_cast<float>(k - half_));
      ys_.push_back(static_cast<float>(r - half_));
    }
  }
}

bool PatchRefiner::fits(cv::Size size, cv::Point2f uv, const PatchWarp& warp) const {
  return corners_inside(size, half_, warp.A, uv);
}

bool PatchRefiner::sample(const cv::Mat& img, const Eigen::Matrix2f& A, cv::Point2f c,
                          float* buf) const {
  return sample_grid(img, half_, A, c, buf, xs_.data(), ys_.data());
}

std::shared_ptr<const PatchTemplate> PatchRefiner::make_template(const cv::Mat& img,
                                                                 cv::Point2f uv) const {
  const int n = 2 * half_ + 1, m = n + 2;
  std::vector<float> big(static_cast<std::size_t>(m * m));
  // One-pixel apron for the central-difference gradients.
  if (!sample_grid(img, half_ + 1, Eigen::Matrix2f::Identity(), uv, big.data())) return nullptr;
  auto t = std::make_shared<PatchTemplate>();
  t->half = half_;
  const std::size_t N = static_cast<std::size_t>(n * n);
  t->value.resize(N);
  t->gx.resize(N);
  t->gy.resize(N);
  double mean = 0.0;
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  for (int r = 0; r < n; ++r) {
    for (int k = 0; k < n; ++k) {
      const auto at = [&](int rr, int kk) { return big[static_cast<std::size_t>(rr * m + kk)]; };
      const std::size_t i = static_cast<std::size_t>(r * n + k);
      t->value[i] = at(r + 1, k + 1);
      t->gx[i] = 0.5f * (at(r + 1, k + 2) - at(r + 1, k));
      t->gy[i] = 0.5f * (at(r + 2, k + 1) - at(r, k + 1));
      mean += t->value[i];
      const double x = k - half_, y = r - half_, gx = t->gx[i], gy = t->gy[i];
      Eigen::Matrix<double, 6, 1> sd;
      sd << gx * x, gy * x, gx * y, gy * y, gx, gy;
      H.selfadjointView<Eigen::Upper>().rankUpdate(sd);
    }
  }
  H = H.selfadjointView<Eigen::Upper>();
  mean /= static_cast<double>(N);
  double norm2 = 0.0;
  for (auto& v : t->value) {
    v -= static_cast<float>(mean);
    norm2 += static_cast<double>(v) * v;
  }
  t->norm = static_cast<float>(std::sqrt(norm2));
  // Translation must be well observed (a corner, not an edge).
  const Eigen::Matrix2d Ht = H.bottomRightCorner<2, 2>();
  const double tr = Ht.trace();
  if (!(tr > 0.0) || Ht.determinant() < 1e-4 * tr * tr || t->norm < 1.0f) return nullptr;
  // Prior on the shape change within one frame (see refine()).
  const double prior = std::max(1e-9, shape_prior_) * H.topLeftCorner<4, 4>().trace() / 4.0;
  for (int d = 0; d < 4; ++d) H(d, d) += prior;
  t->prior = static_cast<float>(prior);
  t->H_inv = H.inverse().cast<float>();
  return t;
}

RefineResult PatchRefiner::refine(const cv::Mat& img, const PatchTemplate& t, cv::Point2f uv,
                                  PatchWarp* warp) const {
  RefineResult res;
  const int n = 2 * half_ + 1;
  const std::size_t N = static_cast<std::size_t>(n * n);
  float buf[64 * 64];
  if (N > sizeof(buf) / sizeof(float) || t.half != half_) return res;
  // Shape prior: with M = A_start^-1 A the shape change so far in this frame and q its
  // parameters, an IC step dp changes q to about q - dp; minimising the data term plus
  // prior |q - dp|^2 gives (H + prior) dp = b + prior q.
  const Eigen::Matrix2f A_start_inv = warp->A.inverse();
  Eigen::Matrix2f A = warp->A;
  cv::Point2f c = uv;
  using Arr = Eigen::Map<const Eigen::ArrayXf>;
  const Arr T(t.value.data(), static_cast<Eigen::Index>(N));
  const Arr GX(t.gx.data(), static_cast<Eigen::Index>(N)), GY(t.gy.data(), static_cast<Eigen::Index>(N));
  const Arr X(xs_.data(), static_cast<Eigen::Index>(N)), Y(ys_.data(), static_cast<Eigen::Index>(N));
  Eigen::Map<Eigen::ArrayXf> I(buf, static_cast<Eigen::Index>(N));
  float zncc = -1.f;
  for (int it = 0; it < max_iterations_; ++it) {
    if (!sample(img, A, c, buf)) return res;
    // Eigen reductions (vectorized; plain float loops would not be, without -ffast-math).
    I -= I.mean();
    const float norm2 = I.square().sum();
    if (norm2 < 1e-6f) return res;
    const float inv_norm = 1.f / std::sqrt(norm2);
    // ZNCC at the pose this step starts from; the final step is below epsilon_px, so this is
    // the score of the returned alignment (saves one more sampling pass).
    zncc = (I * T).sum() * inv_norm / t.norm;
    const float gain = t.norm * inv_norm;
    // Expressions, not temporaries: fused into each reduction, no allocation.
    const auto e = I * gain - T;
    const auto ex = e * GX;
    const auto ey = e * GY;
    Eigen::Matrix<float, 6, 1> b;
    b << (ex * X).sum(), (ey * X).sum(), (ex * Y).sum(), (ey * Y).sum(), ex.sum(), ey.sum();
    const Eigen::Matrix2f M = A_start_inv * A;
    b[0] += t.prior * (M(0, 0) - 1.f);
    b[1] += t.prior * M(1, 0);
    b[2] += t.prior * M(0, 1);
    b[3] += t.prior * (M(1, 1) - 1.f);
    const Eigen::Matrix<float, 6, 1> dp = t.H_inv * b;
    // W <- W o W(dp)^-1: A' = A (I + D)^-1, c' = c - A' d.
    Eigen::Matrix2f D;
    D << 1.f + dp[0], dp[2], dp[1], 1.f + dp[3];
    const float det = D.determinant();
    if (!(std::abs(det) > 1e-3f)) return res;
    A = A * D.inverse();
    const Eigen::Vector2f step = A * Eigen::Vector2f(dp[4], dp[5]);
    c.x -= step.x();
    c.y -= step.y();
    res.iterations = it + 1;
    if (!std::isfinite(c.x) || !std::isfinite(c.y)) return res;
    if (step.norm() < epsilon_px_) break;
  }
  // A sane shape: no flips, no collapse or blow-up beyond a factor 2 in area.
  const float detA = A.determinant();
  if (!(detA > 0.25f && detA < 4.f)) return res;
  res.zncc = zncc;
  res.ok = true;
  res.uv = c;
  warp->A = A;
  return res;
}

float PatchRefiner::zncc(const cv::Mat& img, const PatchTemplate& t, cv::Point2f uv,
                         const PatchWarp& warp) const {
  const int n = 2 * half_ + 1;
  const std::size_t N = static_cast<std::size_t>(n * n);
  float buf[64 * 64];
  if (N > sizeof(buf) / sizeof(float) || !sample(img, warp.A, uv, buf)) return -1.f;
  float mean = 0.f;
  for (std::size_t i = 0; i < N; ++i) mean += buf[i];
  mean /= static_cast<float>(N);
  float dot = 0.f, norm2 = 0.f;
  for (std::size_t i = 0; i < N; ++i) {
    const float v = buf[i] - mean;
    dot += v * t.value[i];
    norm2 += v * v;
  }
  if (norm2 < 1e-6f || t.norm <= 0.f) return 0.f;
  return dot / (std::sqrt(norm2) * t.norm);
}

}  // namespace vid
