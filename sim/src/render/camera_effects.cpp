/// @file camera_effects.cpp
/// @brief The image formation model of camera_effects.h: exposure with motion blur, rolling
/// shutter, vignetting, flicker, analog gain, shot + read noise, auto-exposure; and the
/// per-frame appearance of a scenario's images.
#include "sim/render/camera_effects.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "frontend/camera_model.h"
#include "render_internal.h"
#include "sim/render/random.h"
#include "sim/render/renderer.h"

namespace vid::sim {

namespace {
// Sub-poses of an exposure at most this far apart in the image [px]: together with the
// pixel's own area (supersampling) the steps then read as one continuous smear.
constexpr double kBlurStepPx = 1.0;
}  // namespace

AutoExposure::AutoExposure(const AutoExposureConfig& config, double reference_exposure_s)
    : config_(config), reference_s_(reference_exposure_s) {
  exposure_s_ = std::clamp(reference_exposure_s, config_.min_exposure_s, config_.max_exposure_s);
}

void AutoExposure::set_factor(double factor) {
  const double want_s = factor * reference_s_;
  exposure_s_ = std::clamp(want_s, config_.min_exposure_s, config_.max_exposure_s);
  gain_ = std::clamp(want_s / exposure_s_, 1.0, config_.max_gain);
}

void AutoExposure::update(double mean_level) {
  // Log-domain correction; a black image would ask for an infinite step.
  const double ratio = config_.target_level / std::max(mean_level, 0.5);
  set_factor(factor() * (metered_ ? std::pow(ratio, config_.rate) : ratio));
  metered_ = true;
}

double flicker_factor(double amplitude, double hz, double phase, double t_s, double exposure_s) {
  if (amplitude == 0.0) return 1.0;
  // Mean of sin over the window: sin(centre) * sinc(pi hz e).
  const double x = std::numbers::pi * hz * exposure_s;
  const double sinc = x < 1e-9 ? 1.0 : std::sin(x) / x;
  return 1.0 + amplitude * sinc * std::sin(2.0 * std::numbers::pi * hz * t_s + phase);
}

void apply_auto_exposure(const AutoExposure& ae, FrameAppearance* app) {
  app->exposure_s = ae.exposure_s();
  app->analog_gain = ae.gain();
  app->gain *= ae.factor();
}

int Renderer::blur_samples(const PoseAtTime& T_WC_at, double exposure_s, int max_samples) const {
  if (exposure_s <= 0.0 || max_samples <= 1) return 1;
  const Eigen::Isometry3d T_WC = T_WC_at(0.0);
  const Eigen::Isometry3d T_CW_begin = T_WC_at(-0.5 * exposure_s).inverse();
  const Eigen::Isometry3d T_CW_end = T_WC_at(0.5 * exposure_s).inverse();
  double max_px = 0.0;
  for (int iy = 0; iy < 5; ++iy) {  // 5 x 5 probe pixels over the image
    for (int ix = 0; ix < 5; ++ix) {
      const Eigen::Vector2d uv((ix + 0.5) * width_ / 5.0, (iy + 0.5) * height_ / 5.0);
      Eigen::Vector3d b_C;
      if (!camera_->unproject(uv, &b_C)) continue;
      const auto p_W = scene_.raycast(T_WC.translation(), T_WC.linear() * b_C);
      if (!p_W) continue;
      Eigen::Vector2d a, b;
      if (camera_->project(T_CW_begin * *p_W, &a) && camera_->project(T_CW_end * *p_W, &b)) {
        max_px = std::max(max_px, (a - b).norm());
      }
    }
  }
  return std::clamp(static_cast<int>(std::ceil(max_px / kBlurStepPx)), 1, max_samples);
}

void Renderer::render(const PoseAtTime& T_WC_at, const FrameAppearance& app, cv::Mat* out) const {
  if (app.exposure_s <= 0.0 && app.line_delay_s <= 0.0) {
    render(T_WC_at(0.0), app, out);
    return;
  }
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  const int samples = blur_samples(T_WC_at, app.exposure_s, app.exposure_samples);
  auto one_exposure = [&](double dt_s, float* dst) {
    if (app.line_delay_s > 0.0) {
      render_radiance_rows(T_WC_at, dt_s, app.line_delay_s, dst);
    } else {
      render_radiance(T_WC_at(dt_s), dst);
    }
  };
  radiance_.resize(n);
  if (samples == 1) {
    one_exposure(0.0, radiance_.data());
  } else {
    std::fill(radiance_.begin(), radiance_.end(), 0.0f);
    sub_radiance_.resize(n);
    for (int k = 0; k < samples; ++k) {  // sub-poses evenly spread over [-e/2, e/2]
      one_exposure(app.exposure_s * ((k + 0.5) / samples - 0.5), sub_radiance_.data());
      for (std::size_t i = 0; i < n; ++i) radiance_[i] += sub_radiance_[i];
    }
    const float inv = 1.0f / static_cast<float>(samples);
    for (float& r : radiance_) r *= inv;
  }
  expose(app, out);
}

void Renderer::expose_with_effects(const FrameAppearance& app, cv::Mat* out) const {
  out->create(height_, width_, CV_8UC1);
  if (app.vignetting != 0.0 && vignette_strength_ != app.vignetting) {
    const double cx = camera_->calib().intrinsics[2], cy = camera_->calib().intrinsics[3];
    const double dx = std::max(cx, width_ - 1 - cx), dy = std::max(cy, height_ - 1 - cy);
    const double inv_r2 = 1.0 / (dx * dx + dy * dy);  // farthest corner: rho = 1
    vignette_.resize(static_cast<std::size_t>(width_) * height_);
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        const double rho2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) * inv_r2;
        vignette_[static_cast<std::size_t>(y) * width_ + x] =
            static_cast<float>(vignetting_factor(app.vignetting, rho2));
      }
    }
    vignette_strength_ = app.vignetting;
  }
  const bool vignette = app.vignetting != 0.0;
  const float offset = static_cast<float>(app.offset);
  const float read = static_cast<float>(app.noise_sigma * app.analog_gain);
  const float read2 = read * read;
  // Shot noise variance in gray levels^2 per gray level: G / electrons_per_level.
  const float shot = app.electrons_per_level > 0.0
                         ? static_cast<float>(app.analog_gain / app.electrons_per_level)
                         : 0.0f;
  const auto& table = detail::normal_table();
  Rng rng(app.noise_seed);
  std::uint64_t bits = 0;
  int left = 0;
  for (int y = 0; y < height_; ++y) {
    const float row_gain = static_cast<float>(
        app.gain * flicker_factor(app.flicker_amplitude, app.flicker_hz, app.flicker_phase,
                                  app.t_s + y * app.line_delay_s, app.exposure_s));
    std::uint8_t* row = out->ptr<std::uint8_t>(y);
    const std::size_t i0 = static_cast<std::size_t>(y) * width_;
    const float* rad = &radiance_[i0];
    const float* vig = vignette ? &vignette_[i0] : nullptr;
    for (int x = 0; x < width_; ++x) {
      float v = row_gain * rad[x] * (vig ? vig[x] : 1.0f) + offset;
      const float var = read2 + shot * std::max(v, 0.0f);
      if (var > 0.0f) {
        if (left == 0) {
          bits = rng.next();
          left = 4;
        }
        v += std::sqrt(var) * table[bits & 0xFFFF];
        bits >>= 16;
        --left;
      }
      row[x] = static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f) + 0.5f);
    }
  }
}

FrameAppearance appearance_for_frame(const RenderConfig& c, std::int64_t t_ns, int cam_id,
                                     std::uint64_t frame_index) {
  FrameAppearance a;
  const double t_s = static_cast<double>(t_ns) * 1e-9;
  Rng phase_rng(derive_seed(c.seed, 77));
  const double phase = phase_rng.uniform(0.0, 2.0 * std::numbers::pi);
  const double drift = c.brightness_period_s > 0.0
                           ? c.brightness_amplitude *
                                 std::sin(2.0 * std::numbers::pi * t_s / c.brightness_period_s + phase)
                           : 0.0;
  const std::uint64_t stream = frame_index * 16 + static_cast<std::uint64_t>(cam_id);
  Rng jitter_rng(derive_seed(c.seed, 1000 + 2 * stream));
  a.gain = std::max(0.05, 1.0 + drift + c.brightness_jitter * jitter_rng.normal());
  a.offset = 0.0;
  a.noise_sigma = c.noise_sigma;
  a.noise_seed = derive_seed(c.seed, 1001 + 2 * stream);
  a.gain *= c.illumination;
  a.exposure_s = c.exposure_s;
  a.exposure_samples = c.exposure_samples;
  a.line_delay_s = c.line_delay_s;
  a.electrons_per_level = c.electrons_per_level;
  a.vignetting = c.vignetting;
  a.flicker_amplitude = c.flicker_amplitude;
  a.flicker_hz = c.flicker_hz;
  a.t_s = t_s;
  if (c.flicker_amplitude != 0.0) {  // own stream: the other draws do not depend on it
    Rng flicker_rng(derive_seed(c.seed, 78));
    a.flicker_phase = flicker_rng.uniform(0.0, 2.0 * std::numbers::pi);
  }
  return a;
}

}  // namespace vid::sim
