#pragma once
/// @file renderer.h
/// @brief Per-pixel ray-casting renderer of a Scene through an exact camera model
/// (distorted images: every sample ray is the model's unprojection of its sub-pixel), with
/// n x n supersampling, optional brightness changes and Gaussian noise; 8-bit grayscale.
/// Exposure (motion blur), rolling shutter, vignetting, shot noise, flicker and auto-exposure:
/// the image formation model of camera_effects.h, all off by default.
///
/// Scenario YAML section (all optional):
/// ```yaml
/// render:
///   supersampling: 2            # n x n samples per pixel (1..4)
///   noise_sigma: 2.0            # Gaussian image noise [gray levels]
///   brightness_amplitude: 0.1   # slow global gain drift, relative (0.1 = +-10 %)
///   brightness_period_s: 10.0   # period of the drift
///   brightness_jitter: 0.02     # per-frame, per-camera random gain (exposure) std, relative
///   seed: 1                     # noise and brightness seed (vid_sim may mix in --seed)
///   exposure_s: 0.0             # exposure time e_ref [s] (motion blur); 0 = instantaneous
///   exposure_samples: 16        # most sub-poses averaged over one exposure
///   line_delay_s: 0.0           # rolling shutter: row y exposed at t + y * line_delay_s
///   vignetting: 0.0             # brightness loss at the image corners (0.3 = -30 %)
///   electrons_per_level: 0.0    # shot noise: photo-electrons per gray level at gain 1 (0 = none)
///   illumination: 1.0           # room light level relative to the textures' levels
///   flicker_amplitude: 0.0      # mains flicker of the light, relative
///   flicker_hz: 100.0
///   auto_exposure:              # present = on
///     target_level: 110
///     min_exposure_s: 5.0e-5
///     max_exposure_s: 0.02
///     max_gain: 8.0
///     rate: 0.5
/// ```

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/render/camera_effects.h"
#include "sim/render/scene.h"
#include "types/calibration.h"

namespace YAML {
class Node;
}

namespace vid {
class CameraModel;
}

namespace vid::sim {

/// @brief Image formation settings of a scenario.
struct RenderConfig {
  int supersampling = 2;
  double noise_sigma = 0.0;
  double brightness_amplitude = 0.0;
  double brightness_period_s = 10.0;
  double brightness_jitter = 0.0;
  std::uint64_t seed = 1;
  double exposure_s = 0.0;
  int exposure_samples = 16;
  double line_delay_s = 0.0;
  double vignetting = 0.0;
  double electrons_per_level = 0.0;
  double illumination = 1.0;
  double flicker_amplitude = 0.0;
  double flicker_hz = 100.0;
  AutoExposureConfig auto_exposure;
};

/// @brief Parse (with io::YamlMap; a null node = all defaults) a `render:` YAML map (strict keys; errors name file and key).
RenderConfig parse_render_config(const YAML::Node& node, const std::string& file);

/// @brief Settings of one image: out = gain * V * flicker * radiance + offset + noise (the
/// model of camera_effects.h; with the defaults: gain * radiance + offset + N(0, sigma^2)).
struct FrameAppearance {
  double gain = 1.0;         ///< everything multiplying the radiance except V and flicker
  double offset = 0.0;
  double noise_sigma = 0.0;  ///< read noise at unit analog gain [gray levels]
  std::uint64_t noise_seed = 0;
  double exposure_s = 0.0;   ///< this image's exposure (motion blur); 0 = instantaneous
  int exposure_samples = 16; ///< most sub-poses over the exposure
  double line_delay_s = 0.0; ///< rolling shutter row delay
  double analog_gain = 1.0;  ///< G (part of gain): scales read and shot noise
  double electrons_per_level = 0.0;  ///< at unit gain; 0 = no shot noise
  double vignetting = 0.0;
  double flicker_amplitude = 0.0, flicker_hz = 100.0, flicker_phase = 0.0;
  double t_s = 0.0;          ///< image time (flicker phase)
  /// @brief True if any sensor effect beyond gain, offset and read noise is on.
  bool sensor_effects() const {
    return vignetting != 0.0 || electrons_per_level > 0.0 || flicker_amplitude != 0.0 ||
           analog_gain != 1.0;
  }
};

/// @brief Appearance of image `frame_index` of camera `cam_id` at time t_ns: a slow global
/// sinusoidal gain drift shared by all cameras plus per-camera exposure jitter and noise,
/// all derived deterministically from config.seed, times `illumination`; the config's
/// exposure, rolling shutter, vignetting, shot noise and flicker. Auto-exposure is applied on
/// top by the caller (apply_auto_exposure), as it depends on the previous images.
FrameAppearance appearance_for_frame(const RenderConfig& config, std::int64_t t_ns, int cam_id,
                                     std::uint64_t frame_index);

/// @brief Apply the auto-exposure's current exposure and gain to an image's appearance.
void apply_auto_exposure(const AutoExposure& ae, FrameAppearance* app);

/// @brief Renders one camera. Precomputes all sample rays once (the distortion is fixed), so
/// a frame costs one ray cast per sample. Not thread-safe per instance (scratch buffers).
class Renderer {
 public:
  /// @brief Tile edge [px]: rays are culled against boxes per tile.
  static constexpr int kTileSize = 16;

  /// @brief The scene must outlive the renderer. supersampling in 1..4.
  Renderer(const Scene& scene, const CameraCalib& calib, int supersampling = 2);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// @brief Render the image of a camera at pose T_WC (camera in world).
  cv::Mat render(const Eigen::Isometry3d& T_WC, const FrameAppearance& appearance = {}) const;
  /// @brief As above, into `out` (reallocated only if its size/type differs).
  void render(const Eigen::Isometry3d& T_WC, const FrameAppearance& appearance,
              cv::Mat* out) const;
  /// @brief Render one exposure: radiance averaged over the exposure (motion blur from the
  /// poses T_WC_at(dt) in the window), rows read out with the rolling shutter, then the sensor
  /// model (camera_effects.h). T_WC_at(dt) is the camera pose dt seconds after the image time.
  /// With appearance.exposure_s = line_delay_s = 0 this is render(T_WC_at(0), ...).
  void render(const PoseAtTime& T_WC_at, const FrameAppearance& appearance, cv::Mat* out) const;
  /// @brief Number of sub-poses render() averages over an exposure of exposure_s: one per
  /// pixel of image motion in the window (probed at a few pixels), in 1..max_samples.
  int blur_samples(const PoseAtTime& T_WC_at, double exposure_s, int max_samples) const;

  /// @brief Scene radiance (gray levels at unit gain; mean of the samples of each pixel) seen
  /// from pose T_WC, into out (width * height floats, overwritten).
  void render_radiance(const Eigen::Isometry3d& T_WC, float* out) const;
  /// @brief As above, but pixel row y seen from pose T_WC_at(t0_s + y * line_delay_s): one
  /// rolling-shutter readout.
  void render_radiance_rows(const PoseAtTime& T_WC_at, double t0_s, double line_delay_s,
                            float* out) const;

  /// @brief The camera model used for unprojection.
  const CameraModel& camera() const { return *camera_; }
  int supersampling() const { return ss_; }

 private:
  struct FastSurface;  ///< flattened texture access of one surface (renderer.cpp)
  /// Everything of one camera pose the inner loop needs (boxes' bounding cones in C).
  struct PoseSetup {
    Eigen::Isometry3d T_WC;
    bool free = true;  ///< camera inside the room and outside every box (else generic path)
    Eigen::Matrix3f R;
    Eigen::Vector3f o;
    std::vector<float> b_ang;
    std::vector<Eigen::Vector3f> b_dir;
    std::vector<char> b_always;
  };
  /// Four sample rays (SIMD lanes) in the camera frame and the pixel each belongs to
  /// (-1: padding or a ray the model cannot unproject; it contributes black).
  struct Chunk {
    float x[4], y[4], z[4];
    std::int32_t pix[4];
  };
  /// 16x16 pixel tile: its chunks and a cone bounding its rays, for culling boxes per tile.
  struct Tile {
    std::size_t chunk_begin, chunk_end;
    std::uint32_t row_begin[kTileSize + 1];  ///< first chunk of each pixel row of the tile
    Eigen::Vector3f axis_C;  ///< unit mean direction of the tile's sample rays
    float half_angle;        ///< max angle between axis_C and any sample ray [rad]
  };
  void precompute_rays();
  void build_surface_table();
  PoseSetup setup_pose(const Eigen::Isometry3d& T_WC) const;
  /// Add the samples of chunks [chunk_begin, chunk_end) of `tile` seen from pose p to out.
  void trace(const PoseSetup& p, const Tile& tile, std::size_t chunk_begin, std::size_t chunk_end,
             float* out) const;
  void trace_generic(const Eigen::Isometry3d& T_WC, std::size_t chunk_begin, std::size_t chunk_end,
                     float* out) const;

  const Scene& scene_;
  std::unique_ptr<CameraModel> camera_;
  int ss_;
  int width_, height_;
  std::vector<Chunk> chunks_;  ///< all sample rays, tile by tile
  std::vector<Tile> tiles_;
  std::vector<FastSurface> fs_;  ///< per scene surface, built once
  std::vector<Eigen::Vector3f> box_lo_, box_hi_;
  /// Sensor model: radiance_ -> 8-bit image.
  void expose(const FrameAppearance& app, cv::Mat* out) const;
  /// Sensor model with vignetting, flicker, analog gain, shot noise (camera_effects.cpp).
  void expose_with_effects(const FrameAppearance& app, cv::Mat* out) const;
  mutable std::vector<float> radiance_;  ///< scratch: per-pixel mean of samples
  mutable std::vector<float> sub_radiance_;  ///< scratch: one sub-pose of an exposure
  mutable std::vector<float> vignette_;      ///< V per pixel for vignette_strength_
  mutable double vignette_strength_ = -1.0;
};

}  // namespace vid::sim
