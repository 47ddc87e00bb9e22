#pragma once
/// @file dataset_writer.h
/// @brief Writes an EuRoC/ASL folder (docs/formats.md §1) stream by stream, flushing as it goes.

#include <filesystem>
#include <memory>
#include <vector>

#include "io/errors.h"
#include "types/calibration.h"
#include "types/measurements.h"

namespace cv {
class Mat;
}

namespace vid::io {

/// @brief Writer of a dataset folder ROOT/mav0/... . Files are created on first use.
///
/// Numbers are written in the shortest form that parses back to the same double, so
/// write -> DatasetReader returns identical values. Every row is flushed when written. The
/// writer refuses (DatasetError naming the file) what the reader would reject: timestamps not
/// strictly increasing per stream (per frame for feat0), negative timestamps, NaN/Inf, rotor
/// samples whose length changes, non-CV_8UC1 images, and writes after close(). A FeatureFrame
/// with no observations writes no row.
class DatasetWriter {
 public:
  explicit DatasetWriter(const std::filesystem::path& root);
  ~DatasetWriter();
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;

  void write_imu_calibration(const ImuNoise& imu);
  void write_camera_calibration(const CameraCalib& cam);  ///< camN/sensor.yaml
  void write_rotor_calibration(const RotorSensor& rotor);
  void write_vehicle(const VehicleParams& vehicle);

  void write(const ImuSample& s);
  void write(const RotorSample& s);
  void write(const ThrustSample& s);
  void write(const ForceSample& s);
  void write(const MassSample& s);
  void write(const GroundTruthSample& s);
  void write(const FeatureFrame& f);  ///< feat0/data.csv rows (distorted pixels)
  /// @brief camN/data/<t_ns>.png (8-bit grayscale) and its camN/data.csv row.
  void write_image(int cam_id, TimeNs t_ns, const cv::Mat& gray8);

  /// @brief Flush and close every file (also done by the destructor).
  void close();

  const std::filesystem::path& mav0() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vid::io
