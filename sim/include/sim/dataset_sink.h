#pragma once
/// @file dataset_sink.h
/// @brief SimSink that writes a docs/formats.md §1 folder through vid::io::DatasetWriter, forwarding
/// camera triggers to the visual output (rendered images and/or feat0 + landmarks.csv).

#include <filesystem>
#include <fstream>
#include <memory>

#include "io/dataset_writer.h"
#include "sim/scenario.h"
#include "sim/simulator.h"

namespace vid::sim {

/// @brief Produces camera data at a camera trigger (images, features). Implemented on top of
/// the render module in visual_output.cpp.
class VisualOutput {
 public:
  virtual ~VisualOutput() = default;
  /// @brief One camera trigger: body pose and motion at the image time (stamp t_ns).
  virtual void on_camera(TimeNs t_ns, std::uint64_t frame_index, const Eigen::Isometry3d& T_WI,
                         const BodyMotion& motion, io::DatasetWriter& writer) = 0;
  /// @brief Write end-of-run files (landmarks.csv, positions rotated by R_GS into the
  /// ground-truth world) into mav0.
  virtual void finish(io::DatasetWriter& writer, const Eigen::Matrix3d& R_GS) = 0;
};

/// @brief Visual output of a scenario, or nullptr when it has no cameras. Throws
/// std::runtime_error if images/features are requested but the render module is missing.
std::unique_ptr<VisualOutput> make_visual_output(const Scenario& scenario);

/// @brief Writes every stream of a scenario into root/mav0/...
///
/// World-frame ground truth (poses, velocities, external force, landmarks) is written in the
/// ground-truth world G = R_GS * simulation world (Simulator::R_GS, a rotation about gravity
/// that sets the initial heading); body-frame streams (IMU, rotors, images, features) do not
/// depend on it.
class DatasetSink : public SimSink {
 public:
  /// @param visual may be null (no camera data).
  /// @param R_GS rotation from the simulation world to the written ground-truth world.
  DatasetSink(const std::filesystem::path& root, const Scenario& scenario,
              std::unique_ptr<VisualOutput> visual,
              const Eigen::Matrix3d& R_GS = Eigen::Matrix3d::Identity());
  ~DatasetSink() override;
  void on_imu(const ImuSample& s) override { writer_.write(s); }
  void on_rotor(const RotorSample& s) override { writer_.write(s); }
  void on_groundtruth(const GroundTruthSample& s) override;
  void on_force(const ForceSample& s) override;
  void on_mass(const MassSample& s) override { writer_.write(s); }
  /// @brief phase0/data.csv `#timestamp [ns],phase` (0 on_ground, 1 airborne; docs/formats.md §1).
  void on_phase(const PhaseSample& s) override;
  /// @brief mav0/time_offset0/data.csv: `#timestamp [ns],time_offset [s]` per camera stamp
  /// (truth for the estimator's online time offset; t_imu = t_cam + offset).
  void on_time_offset(TimeNs t_ns, double offset_s) override;
  void on_camera_trigger(TimeNs t_ns, std::uint64_t frame_index, const Eigen::Isometry3d& T_WI,
                         const BodyMotion& motion) override;
  /// @brief Write landmarks and close all files.
  void finish();
  std::uint64_t camera_frames() const { return frames_; }

 private:
  io::DatasetWriter writer_;
  std::unique_ptr<VisualOutput> visual_;
  Eigen::Matrix3d R_GS_;
  std::ofstream phase_;  ///< opened at the first phase sample (scenarios with `ground:`)
  std::ofstream time_offset_;  ///< opened at the first offset sample (`cameras.time_offset_s`)
  std::uint64_t frames_ = 0;
  bool finished_ = false;
};

}  // namespace vid::sim
