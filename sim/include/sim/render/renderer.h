#pragma once
/// @file renderer.h
/// @brief Per-pixel ray-casting renderer of a Scene through an exact camera model
/// (distorted images: every sample ray is the model's unprojection of its sub-pixel), with
/// n x n supersampling, optional brightness changes and Gaussian noise; 8-bit grayscale.
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
/// ```

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/render/scene.h"
#include "vio_core/calibration.h"

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
};

/// @brief Parse (with io::YamlMap; a null node = all defaults) a `render:` YAML map (strict keys; errors name file and key).
RenderConfig parse_render_config(const YAML::Node& node, const std::string& file);

/// @brief Photometric settings of one image: out = gain * radiance + offset + N(0, sigma^2).
struct FrameAppearance {
  double gain = 1.0;
  double offset = 0.0;
  double noise_sigma = 0.0;
  std::uint64_t noise_seed = 0;
};

/// @brief Appearance of image `frame_index` of camera `cam_id` at time t_ns: a slow global
/// sinusoidal gain drift shared by all cameras plus per-camera exposure jitter and noise,
/// all derived deterministically from config.seed.
FrameAppearance appearance_for_frame(const RenderConfig& config, std::int64_t t_ns, int cam_id,
                                     std::uint64_t frame_index);

/// @brief Renders one camera. Precomputes all sample rays once (the distortion is fixed), so
/// a frame costs one ray cast per sample. Not thread-safe per instance (scratch buffers).
class Renderer {
 public:
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

  /// @brief The camera model used for unprojection.
  const CameraModel& camera() const { return *camera_; }
  int supersampling() const { return ss_; }

 private:
  /// Four sample rays (SIMD lanes) in the camera frame and the pixel each belongs to
  /// (-1: padding or a ray the model cannot unproject; it contributes black).
  struct Chunk {
    float x[4], y[4], z[4];
    std::int32_t pix[4];
  };
  /// 16x16 pixel tile: its chunks and a cone bounding its rays, for culling boxes per tile.
  struct Tile {
    std::size_t chunk_begin, chunk_end;
    Eigen::Vector3f axis_C;  ///< unit mean direction of the tile's sample rays
    float half_angle;        ///< max angle between axis_C and any sample ray [rad]
  };
  void precompute_rays();
  void render_radiance(const Eigen::Isometry3d& T_WC, float* sum) const;
  void render_radiance_generic(const Eigen::Isometry3d& T_WC, float* sum) const;

  const Scene& scene_;
  std::unique_ptr<CameraModel> camera_;
  int ss_;
  int width_, height_;
  std::vector<Chunk> chunks_;  ///< all sample rays, tile by tile
  std::vector<Tile> tiles_;
  mutable std::vector<float> radiance_;  ///< scratch: per-pixel mean of samples
};

}  // namespace vid::sim
