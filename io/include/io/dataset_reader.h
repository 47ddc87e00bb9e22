#pragma once
/// @file dataset_reader.h
/// @brief Streams an EuRoC/ASL folder (docs/formats.md §1) as one time-ordered sequence of typed
/// measurements, without loading images into memory.

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/errors.h"
#include "types/calibration.h"
#include "types/measurements.h"

namespace vid::io {

/// @brief Anything that yields measurements in timestamp order (folders, LCM, simulator).
class MeasurementSource {
 public:
  virtual ~MeasurementSource() = default;
  /// @brief Next measurement in time order, or std::nullopt at the end.
  virtual std::optional<Measurement> next() = 0;
};

/// @brief How the reader treats imperfect input.
struct ReaderOptions {
  bool drop_bad_timestamps = false;   ///< drop non-monotonic/duplicate rows (counted) instead of throwing
  bool skip_missing_images = false;   ///< skip images listed but absent (counted) instead of throwing
  /// List images that are missing on disk anyway (counted as skipped_missing_images): the consumer
  /// finds them missing when decoding and reports the frame (vid::system::FrameFaults).
  bool list_missing_images = false;
  bool read_images = true;            ///< emit ImageFrame from camN/data.csv
  bool read_features = true;          ///< emit FeatureFrame from feat0/data.csv
  bool read_groundtruth = true;       ///< emit GroundTruthSample, ForceSample, MassSample
  /// Sensor streams (imu0, rotor0, thrust0, camN, feat0): a time gap between two rows longer than
  /// this many sample periods (the median of the stream's first intervals) is an error naming
  /// file, line and gap; 0: no check. Reference streams (ground truth, force0, mass0) may pause.
  double max_gap_periods = 100.0;
  /// Such a gap is passed to @p warn instead of thrown (the estimator then handles it as its
  /// own IMU/rotor gap logic does, counted in summary.json).
  bool gaps_as_warnings = false;
  /// Receives warnings (gaps under gaps_as_warnings); called on the reading thread.
  std::function<void(const std::string&)> warn;
};

/// @brief Calibration found in the folder's sensor.yaml / vehicle.yaml files.
struct DatasetCalibration {
  std::vector<CameraCalib> cameras;     ///< cam0, cam1, ... (sorted by id)
  std::optional<ImuNoise> imu;          ///< imu0/sensor.yaml
  std::optional<RotorSensor> rotor;     ///< rotor0/sensor.yaml
  std::optional<VehicleParams> vehicle; ///< vehicle.yaml
};

/// @brief Per-stream statistics (for the dataset summary and run summaries).
struct StreamStats {
  std::string name;           ///< "imu0", "cam0", "feat0", ...
  std::size_t count = 0;      ///< rows (feat0: frames)
  TimeNs first_ns = 0;
  TimeNs last_ns = 0;
  TimeNs largest_gap_ns = 0;
  TimeNs largest_gap_at_ns = 0;  ///< time of the sample before the largest gap (first_ns if none)
  std::size_t dropped = 0;    ///< rows dropped under ReaderOptions (sum of the two below)
  std::size_t dropped_bad_timestamps = 0;  ///< non-monotonic/duplicate rows (drop_bad_timestamps)
  std::size_t skipped_missing_images = 0;  ///< listed images not on disk (skip_missing_images)
  std::size_t gaps_over_bound = 0;         ///< gaps past max_gap_periods (gaps_as_warnings)
};

/// @brief Reader of a dataset folder (SEQ or SEQ/mav0). Throws DatasetError / ConfigError.
///
/// Every stream is a streaming CSV cursor holding one pending measurement; next() returns the
/// earliest (k-way merge, constant memory). At equal timestamps the order is imu0, rotor0,
/// thrust0, images, feat0, force0, mass0, ground truth. Images are never decoded: the reader
/// only checks that each listed file exists. imu0/data.csv is required; camN/sensor.yaml is
/// required when camN/data.csv or feat0/ uses camera N; rotor0/sensor.yaml when rotor0/ exists.
/// All streams are opened and their first row read by the constructor, so an empty or
/// malformed file start fails there.
class DatasetReader : public MeasurementSource {
 public:
  DatasetReader(const std::filesystem::path& root, ReaderOptions options = {});
  ~DatasetReader() override;
  DatasetReader(const DatasetReader&) = delete;
  DatasetReader& operator=(const DatasetReader&) = delete;

  std::optional<Measurement> next() override;

  /// @brief The folder that holds imu0/, cam0/, ... (the mav0 folder).
  const std::filesystem::path& mav0() const;
  const DatasetCalibration& calibration() const;
  /// @brief Which streams exist ("imu0", "cam0", "cam1", "feat0", "rotor0", "thrust0",
  /// "force0", "mass0", "state_groundtruth_estimate0").
  bool has_stream(const std::string& name) const;
  /// @brief Statistics so far (complete after next() returned nullopt).
  std::vector<StreamStats> stats() const;
  /// @brief Fraction [0, 1] of the opened data.csv bytes consumed so far (for progress bars).
  double progress() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vid::io
