/// @file visual_output.cpp
/// @brief Camera data of a scenario through the render module: rendered images and, when
/// the feature simulator is available, feat0 + landmarks.csv. The one place where the
/// simulator calls into sim/render.

#include <cstdio>
#include <stdexcept>

#include "sim/dataset_sink.h"
#include "sim/render/random.h"
#include "sim/render/renderer.h"
#include "sim/render/scene.h"
#if __has_include("sim/render/feature_simulator.h")
#include "sim/render/feature_simulator.h"
#define VID_SIM_HAS_FEATURES 1
#endif

namespace vid::sim {

namespace {

constexpr std::uint64_t kRenderStream = 4, kFeatureStream = 5;

class RenderedOutput : public VisualOutput {
 public:
  explicit RenderedOutput(const Scenario& sc)
      : sc_(sc),
        scene_(parse_scene_config(sc.scene_node, sc.file)),
        render_cfg_(parse_render_config(sc.render_node, sc.file)) {
    render_cfg_.seed = derive_seed(render_cfg_.seed ^ sc.seed, kRenderStream);
    if (!sc.noise) {
      render_cfg_.noise_sigma = 0.0;
      render_cfg_.brightness_jitter = 0.0;
      render_cfg_.electrons_per_level = 0.0;
    }
    if (sc.cameras.images) {
      for (const CameraCalib& c : sc.cameras.cameras) {
        renderers_.push_back(std::make_unique<Renderer>(scene_, c, render_cfg_.supersampling));
        auto_exposure_.emplace_back(render_cfg_.auto_exposure, render_cfg_.exposure_s);
      }
    }
#ifdef VID_SIM_HAS_FEATURES
    FeatureSimConfig fc =
        parse_feature_sim_config(sc.features_node, sc.file);
    fc.seed = derive_seed(fc.seed ^ sc.seed, kFeatureStream);
    if (!sc.noise) fc.pixel_noise_sigma = 0.0;
    if (sc.cameras.features) features_ = std::make_unique<FeatureSimulator>(scene_, sc.cameras.cameras, fc);
#else
    if (sc.cameras.features && !sc.cameras.images)
      throw std::runtime_error(sc.file + ": feature-level output needs the feature simulator (not built)");
#endif
  }

  void on_camera(TimeNs t_ns, std::uint64_t frame_index, const Eigen::Isometry3d& T_WI,
                 const BodyMotion& motion, io::DatasetWriter& writer) override {
    for (std::size_t i = 0; i < renderers_.size(); ++i) {
      const CameraCalib& c = sc_.cameras.cameras[i];
      FrameAppearance app = appearance_for_frame(render_cfg_, t_ns, c.cam_id, frame_index);
      if (app.exposure_s <= 0.0 && app.line_delay_s <= 0.0 && !render_cfg_.auto_exposure.enabled) {
        renderers_[i]->render(T_WI * c.T_IC, app, &image_);  // instantaneous global shutter
      } else {
        // Constant-acceleration, constant-rate extrapolation over the exposure and readout
        // (milliseconds: the neglected jerk and angular acceleration move a pixel far less
        // than 0.01 px).
        const PoseAtTime T_WC_at = [&](double dt) {
          Eigen::Isometry3d T = T_WI;
          T.translation() += motion.v_WI * dt + 0.5 * dt * dt * motion.a_WI;
          const Eigen::Vector3d rot = motion.w_I * dt;
          if (rot.norm() > 0.0) T.linear() = T_WI.linear() * Eigen::AngleAxisd(rot.norm(), rot.normalized()).toRotationMatrix();
          return T * c.T_IC;
        };
        AutoExposure& ae = auto_exposure_[i];
        if (render_cfg_.auto_exposure.enabled) {
          if (!ae.metered()) {  // meter a first image: the camera ran before the sequence
            FrameAppearance probe = app;
            apply_auto_exposure(ae, &probe);
            renderers_[i]->render(T_WC_at, probe, &image_);
            ae.update(cv::mean(image_)[0]);
          }
          apply_auto_exposure(ae, &app);
        }
        renderers_[i]->render(T_WC_at, app, &image_);
        if (render_cfg_.auto_exposure.enabled) ae.update(cv::mean(image_)[0]);
      }
      writer.write_image(c.cam_id, t_ns, image_);
    }
#ifdef VID_SIM_HAS_FEATURES
    if (features_) writer.write(features_->step(t_ns, T_WI));
#endif
  }

  /// @brief landmarks.csv: every landmark the feature simulator created (id == feature id).
  void finish(io::DatasetWriter& writer, const Eigen::Matrix3d& R_GS) override {
#ifdef VID_SIM_HAS_FEATURES
    if (!features_) return;
    const std::filesystem::path path = writer.mav0() / "landmarks.csv";
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw std::runtime_error(path.string() + ": cannot write");
    std::fprintf(f, "#id,x,y,z\n");
    for (const Landmark& l : features_->landmarks()) {
      const Eigen::Vector3d p_G = R_GS * l.p_W;
      std::fprintf(f, "%llu,%.17g,%.17g,%.17g\n", static_cast<unsigned long long>(l.id), p_G.x(), p_G.y(), p_G.z());
    }
    if (std::fclose(f) != 0) throw std::runtime_error(path.string() + ": write failed");
#else
    (void)writer;
    (void)R_GS;
#endif
  }

 private:
  const Scenario& sc_;
  Scene scene_;
  RenderConfig render_cfg_;
  std::vector<std::unique_ptr<Renderer>> renderers_;
  std::vector<AutoExposure> auto_exposure_;  ///< per camera (used when enabled)
  cv::Mat image_;
#ifdef VID_SIM_HAS_FEATURES
  std::unique_ptr<FeatureSimulator> features_;
#endif
};

}  // namespace

std::unique_ptr<VisualOutput> make_visual_output(const Scenario& sc) {
  if (sc.cameras.cameras.empty() || (!sc.cameras.images && !sc.cameras.features)) return nullptr;
  return std::make_unique<RenderedOutput>(sc);
}

}  // namespace vid::sim
