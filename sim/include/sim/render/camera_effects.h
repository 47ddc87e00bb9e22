#pragma once
/// @file camera_effects.h
/// @brief The camera's image formation beyond the geometry, defined once here. A pixel's gray
/// level is
///
///     level(x, y) = L(x, y) * V(x, y) * b * illumination * flicker(t_y) * (e / e_ref) * G  +  n
///
/// * L: scene radiance, as rendered (the textures' gray levels, averaged over the pixel's
///   samples and over the exposure window: motion blur from the true motion, see below);
///   the textures' levels are what the camera records at the reference exposure e_ref
///   (`render.exposure_s`), gain 1, light 1.
/// * V: vignetting, V = 1 - vignetting * rho^2 with rho the distance to the principal point
///   over the principal point's distance to the farthest image corner (V = 1 - vignetting there).
/// * b = max(0.05, 1 + brightness_amplitude sin(2 pi t / brightness_period_s + phi) +
///   brightness_jitter N(0, 1)): a slow drift of the room light shared by all cameras plus a
///   per-frame, per-camera exposure error (FrameAppearance::gain without the factors below).
/// * illumination: the room's light level (dark room: < 1); flicker(t): mains flicker of the
///   lamps, the mean of 1 + flicker_amplitude sin(2 pi flicker_hz t + phi) over the row's
///   exposure window (a 10 ms exposure under 100 Hz flicker sees none; a rolling shutter
///   sees bands).
/// * e, G: exposure time and analog gain; fixed (e = e_ref, G = 1) or steered by auto-exposure
///   toward a target mean level (exposure first, then gain).
/// * n: sensor noise, Gaussian with variance (noise_sigma G)^2 + level G / electrons_per_level:
///   read noise (`noise_sigma` gray levels at unit gain) plus photon shot noise (the signal is
///   level / G * electrons_per_level photo-electrons, Poisson, approximated as Gaussian).
///
/// Rolling shutter: row y is exposed around t + y * line_delay_s (t = the image time, the first
/// row's mid-exposure); global shutter: line_delay_s = 0. Motion blur: the radiance is the mean
/// over sub-poses evenly spread over [t_y - e/2, t_y + e/2], as many as the image motion in the
/// window needs (one per pixel of motion, at most `exposure_samples`).

#include <Eigen/Geometry>

#include <functional>

namespace vid::sim {

/// @brief Camera pose T_WC at dt_s seconds after the image time.
using PoseAtTime = std::function<Eigen::Isometry3d(double dt_s)>;

/// @brief Auto-exposure settings (scenario YAML `render.auto_exposure`; present = enabled).
struct AutoExposureConfig {
  bool enabled = false;
  double target_level = 110.0;   ///< mean gray level the controller steers to
  double min_exposure_s = 5e-5;
  double max_exposure_s = 0.02;  ///< longest exposure before the gain rises
  double max_gain = 8.0;         ///< highest analog gain
  double rate = 0.5;             ///< fraction of the (log) brightness error corrected per frame
};

/// @brief One camera's auto-exposure: meters each image's mean level and sets the exposure
/// and gain of the next one (exposure first, up to max_exposure_s, then gain). The first
/// metered image is corrected in full (a camera that has been running before the sequence).
class AutoExposure {
 public:
  /// @brief reference_exposure_s: e_ref, the exposure at which the textures' levels are recorded.
  AutoExposure(const AutoExposureConfig& config, double reference_exposure_s);
  /// @brief Update from the mean level of the image taken with the current settings.
  void update(double mean_level);
  double exposure_s() const { return exposure_s_; }
  double gain() const { return gain_; }
  /// @brief (e / e_ref) * G: the brightness factor of the current settings.
  double factor() const { return exposure_s_ * gain_ / reference_s_; }
  bool metered() const { return metered_; }

 private:
  void set_factor(double factor);
  AutoExposureConfig config_;
  double reference_s_;
  double exposure_s_, gain_ = 1.0;
  bool metered_ = false;
};

/// @brief Vignetting factor V at rho^2 (see the file comment).
inline double vignetting_factor(double vignetting, double rho2) { return 1.0 - vignetting * rho2; }

/// @brief Mean of 1 + amplitude sin(2 pi hz t + phase) over an exposure of exposure_s centred on t.
double flicker_factor(double amplitude, double hz, double phase, double t_s, double exposure_s);

}  // namespace vid::sim
