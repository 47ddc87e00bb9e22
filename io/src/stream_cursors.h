#pragma once
/// @file stream_cursors.h
/// @brief (private) One cursor per dataset stream; each holds at most one pending
/// measurement so the reader can k-way merge them in constant memory.

#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "io/csv_reader.h"
#include "io/dataset_reader.h"

namespace vid::io::detail {

/// @brief Row-level timestamp bookkeeping shared by all streams: monotonicity (error or
/// drop-with-count), stats (count, span, largest gap).
class TimedRows {
 public:
  /// @param check_gaps  a sensor stream: apply ReaderOptions::max_gap_periods to it
  TimedRows(const std::filesystem::path& path, std::string name, const ReaderOptions& options,
            bool check_gaps = false);
  /// @brief Next row with exactly @p columns fields (or @p alt_columns when nonzero) whose
  /// timestamp passes the order check (strictly after the last accepted one, or equal when
  /// @p allow_equal). False at end.
  bool next(std::size_t columns, TimeNs* t, bool allow_equal = false, std::size_t alt_columns = 0);
  /// @brief Count an emitted sample at @p t (updates span and largest gap).
  void record(TimeNs t);
  /// @brief Count a row dropped for a missing image.
  void count_missing_image() { ++stats_.dropped; ++stats_.skipped_missing_images; }
  /// @brief Count a row dropped for its timestamp (or a duplicate feature at one timestamp).
  void count_bad_timestamp() { ++stats_.dropped; ++stats_.dropped_bad_timestamps; }
  /// @brief Throw "FILE: no data rows" when nothing was emitted.
  void require_rows() const;
  CsvReader& csv() { return csv_; }
  const CsvReader& csv() const { return csv_; }
  const StreamStats& stats() const { return stats_; }

 private:
  CsvReader csv_;
  StreamStats stats_;
  bool drop_;
  bool have_last_ = false;
  TimeNs last_ = 0;
  std::size_t last_line_ = 0;
  bool have_recorded_ = false;
  /// Gap check: the period is the median of the first kPeriodSamples positive intervals, which
  /// are checked once it is known, every later one as it comes.
  void check_gap(TimeNs gap, std::size_t line);
  static constexpr std::size_t kPeriodSamples = 16;
  double max_gap_periods_ = 0.0;
  bool gaps_warn_ = false;
  std::function<void(const std::string&)> warn_;
  TimeNs period_ = 0;
  std::vector<std::pair<TimeNs, std::size_t>> first_gaps_;  ///< (interval, line) until period_ is known
};

/// @brief A stream of the merge: its pending measurement and statistics.
class Cursor {
 public:
  virtual ~Cursor() = default;
  /// @brief Pending measurement (valid while !done()).
  const Measurement& head() const { return *head_; }
  Measurement take();
  bool done() const { return !head_.has_value(); }
  TimeNs head_time() const { return head_time_; }
  virtual void stats(std::vector<StreamStats>* out) const = 0;
  virtual std::uint64_t bytes_read() const = 0;
  virtual std::uint64_t bytes_total() const = 0;

 protected:
  /// @brief Load the next measurement into head_ (or reset it at the end).
  virtual void advance() = 0;
  std::optional<Measurement> head_;
  TimeNs head_time_ = 0;
};

/// @brief One-row-per-sample CSV (imu0, rotor0, thrust0, force0, mass0, ground truth); rows
/// have @p columns fields, or @p alt_columns when nonzero (optional trailing columns).
using RowParser = std::function<Measurement(const CsvReader&, TimeNs)>;
std::unique_ptr<Cursor> make_row_cursor(const std::filesystem::path& csv, const std::string& name,
                                        std::size_t columns, RowParser parser, const ReaderOptions& options,
                                        std::size_t alt_columns = 0);

/// @brief camN/data.csv files merged into ImageFrames (images of equal timestamp grouped).
std::unique_ptr<Cursor> make_camera_cursor(const std::filesystem::path& mav0, const std::vector<int>& cam_ids,
                                           const ReaderOptions& options);

/// @brief feat0/data.csv rows grouped by timestamp into FeatureFrames.
std::unique_ptr<Cursor> make_feature_cursor(const std::filesystem::path& csv, const std::set<int>& calibrated_cams,
                                            const ReaderOptions& options);

}  // namespace vid::io::detail
