#include "stream_cursors.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <utility>

#include "types/median.h"

namespace vid::io::detail {

// ---------------------------------------------------------------------------------------------
TimedRows::TimedRows(const std::filesystem::path& path, std::string name, const ReaderOptions& options,
                     bool check_gaps)
    : csv_(path),
      drop_(options.drop_bad_timestamps),
      max_gap_periods_(check_gaps ? options.max_gap_periods : 0.0),
      gaps_warn_(options.gaps_as_warnings),
      warn_(options.warn) {
  stats_.name = std::move(name);
}

void TimedRows::check_gap(TimeNs gap, std::size_t line) {
  if (max_gap_periods_ <= 0.0 || gap <= 0) return;
  if (period_ == 0) {
    first_gaps_.emplace_back(gap, line);
    if (first_gaps_.size() < kPeriodSamples) return;
    std::vector<TimeNs> g;
    for (const auto& [d, l] : first_gaps_) g.push_back(d);
    period_ = upper_median(g);
    auto first = std::move(first_gaps_);
    first_gaps_.clear();
    for (const auto& [d, l] : first) check_gap(d, l);
    return;
  }
  if (static_cast<double>(gap) <= max_gap_periods_ * static_cast<double>(period_)) return;
  char text[200];
  std::snprintf(text, sizeof text,
                "line %zu: time gap of %.3f s after the previous row, more than %g sample periods of %.3f ms", line,
                ns_to_s(gap), max_gap_periods_, ns_to_s(period_) * 1e3);
  if (!gaps_warn_) {
    throw DatasetError(csv_.path().string() + ": " + text +
                       " (vid_run --allow-gaps only warns, --max-gap-periods N moves the bound)");
  }
  ++stats_.gaps_over_bound;
  if (warn_) warn_(csv_.path().string() + ": " + text);
}

bool TimedRows::next(std::size_t columns, TimeNs* t, bool allow_equal, std::size_t alt_columns) {
  while (csv_.next_row()) {
    csv_.expect_columns(columns, alt_columns);
    const TimeNs ts = csv_.get_int(0, "timestamp [ns]");
    if (ts < 0) csv_.fail("negative timestamp " + std::to_string(ts));
    if (have_last_ && (ts < last_ || (ts == last_ && !allow_equal))) {
      if (drop_) {
        count_bad_timestamp();
        continue;
      }
      const std::string prev = " (line " + std::to_string(last_line_) + ")";
      if (ts == last_) {
        csv_.fail("duplicate timestamp " + std::to_string(ts) + ", same as the previous row" + prev);
      }
      csv_.fail("timestamps not sorted: " + std::to_string(ts) + " is before the previous row's " +
                std::to_string(last_) + prev);
    }
    if (have_last_) check_gap(ts - last_, csv_.line());
    have_last_ = true;
    last_ = ts;
    last_line_ = csv_.line();
    *t = ts;
    return true;
  }
  return false;
}

void TimedRows::record(TimeNs t) {
  if (!have_recorded_) {
    stats_.first_ns = t;
    stats_.largest_gap_at_ns = t;  // no gap yet: point at the first sample, not at t = 0
    have_recorded_ = true;
  } else if (t - stats_.last_ns > stats_.largest_gap_ns) {
    stats_.largest_gap_ns = t - stats_.last_ns;
    stats_.largest_gap_at_ns = stats_.last_ns;
  }
  stats_.last_ns = t;
  ++stats_.count;
}

void TimedRows::require_rows() const {
  if (stats_.count > 0) return;
  std::string msg = csv_.path().string() + ": no data rows (empty data.csv)";
  if (stats_.dropped > 0) msg += " after dropping " + std::to_string(stats_.dropped) + " rows";
  throw DatasetError(msg);
}

Measurement Cursor::take() {
  Measurement m = std::move(*head_);
  advance();
  return m;
}

// ---------------------------------------------------------------------------------------------
namespace {

class RowCursor final : public Cursor {
 public:
  RowCursor(const std::filesystem::path& csv, const std::string& name, std::size_t columns, std::size_t alt_columns,
            RowParser parser, const ReaderOptions& options)
      : rows_(csv, name, options, /*check_gaps=*/name == "imu0" || name == "rotor0" || name == "thrust0"),
        columns_(columns),
        alt_columns_(alt_columns),
        parser_(std::move(parser)) {
    advance();
    rows_.require_rows();
  }
  void stats(std::vector<StreamStats>* out) const override { out->push_back(rows_.stats()); }
  std::uint64_t bytes_read() const override { return rows_.csv().bytes_read(); }
  std::uint64_t bytes_total() const override { return rows_.csv().bytes_total(); }

 protected:
  void advance() override {
    TimeNs t = 0;
    if (!rows_.next(columns_, &t, false, alt_columns_)) {
      head_.reset();
      return;
    }
    head_ = parser_(rows_.csv(), t);
    head_time_ = t;
    rows_.record(t);
  }

 private:
  TimedRows rows_;
  std::size_t columns_;
  std::size_t alt_columns_;
  RowParser parser_;
};

/// One camera's data.csv: (timestamp, existing image path) rows.
class CameraRows {
 public:
  CameraRows(const std::filesystem::path& mav0, int cam_id, const ReaderOptions& options)
      : cam_id_(cam_id),
        image_dir_(mav0 / ("cam" + std::to_string(cam_id)) / "data"),
        rows_(mav0 / ("cam" + std::to_string(cam_id)) / "data.csv", "cam" + std::to_string(cam_id), options, true),
        skip_missing_(options.skip_missing_images),
        list_missing_(options.list_missing_images) {
    advance();
    rows_.require_rows();
  }
  bool done() const { return !has_head_; }
  TimeNs time() const { return t_; }
  int cam_id() const { return cam_id_; }
  ImageRef take() {
    ImageRef ref{cam_id_, path_};
    advance();
    return ref;
  }
  const TimedRows& rows() const { return rows_; }

 private:
  void advance() {
    TimeNs t = 0;
    while (rows_.next(2, &t)) {
      const std::string_view name = rows_.csv().field(1);
      if (name.empty()) rows_.csv().fail("column 2 'filename': empty file name");
      std::filesystem::path p = image_dir_ / std::string(name);
      std::error_code ec;
      if (!std::filesystem::is_regular_file(p, ec)) {
        if (skip_missing_ || list_missing_) rows_.count_missing_image();
        if (skip_missing_ && !list_missing_) continue;
        if (!list_missing_) rows_.csv().fail("image file missing: " + p.string());
      }
      has_head_ = true;
      t_ = t;
      path_ = p.string();
      rows_.record(t);
      return;
    }
    has_head_ = false;
  }

  int cam_id_;
  std::filesystem::path image_dir_;
  TimedRows rows_;
  bool skip_missing_;
  bool list_missing_;
  bool has_head_ = false;
  TimeNs t_ = 0;
  std::string path_;
};

class CameraCursor final : public Cursor {
 public:
  CameraCursor(const std::filesystem::path& mav0, const std::vector<int>& cam_ids, const ReaderOptions& options) {
    for (int id : cam_ids) cams_.push_back(std::make_unique<CameraRows>(mav0, id, options));
    advance();
  }
  void stats(std::vector<StreamStats>* out) const override {
    for (const auto& c : cams_) out->push_back(c->rows().stats());
  }
  std::uint64_t bytes_read() const override {
    std::uint64_t n = 0;
    for (const auto& c : cams_) n += c->rows().csv().bytes_read();
    return n;
  }
  std::uint64_t bytes_total() const override {
    std::uint64_t n = 0;
    for (const auto& c : cams_) n += c->rows().csv().bytes_total();
    return n;
  }

 protected:
  void advance() override {
    TimeNs t = std::numeric_limits<TimeNs>::max();
    for (const auto& c : cams_) {
      if (!c->done()) t = std::min(t, c->time());
    }
    if (t == std::numeric_limits<TimeNs>::max()) {
      head_.reset();
      return;
    }
    ImageFrame frame;
    frame.t_ns = t;
    for (const auto& c : cams_) {  // cams_ is sorted by id, so images are too
      if (!c->done() && c->time() == t) frame.images.push_back(c->take());
    }
    head_time_ = t;
    head_ = std::move(frame);
  }

 private:
  std::vector<std::unique_ptr<CameraRows>> cams_;
};

class FeatureCursor final : public Cursor {
 public:
  FeatureCursor(const std::filesystem::path& csv, std::set<int> calibrated, const ReaderOptions& options)
      : rows_(csv, "feat0", options, true), calibrated_(std::move(calibrated)), drop_(options.drop_bad_timestamps) {
    read_pending();
    advance();
    rows_.require_rows();
  }
  void stats(std::vector<StreamStats>* out) const override { out->push_back(rows_.stats()); }
  std::uint64_t bytes_read() const override { return rows_.csv().bytes_read(); }
  std::uint64_t bytes_total() const override { return rows_.csv().bytes_total(); }

 protected:
  void advance() override {
    if (!pending_) {
      head_.reset();
      return;
    }
    FeatureFrame frame;
    frame.t_ns = pending_t_;
    std::set<std::pair<int, std::uint64_t>> seen;
    while (pending_ && pending_t_ == frame.t_ns) {
      const auto key = std::make_pair(pending_->cam_id, pending_->feature_id);
      if (!seen.insert(key).second) {
        if (!drop_) {
          rows_.csv().fail("duplicate observation of feature " + std::to_string(key.second) + " in cam" +
                           std::to_string(key.first) + " at timestamp " + std::to_string(frame.t_ns));
        }
        rows_.count_bad_timestamp();  // same (t, cam, id) twice: a duplicate-timestamp row
      } else {
        frame.observations.push_back(*pending_);
      }
      read_pending();
    }
    rows_.record(frame.t_ns);
    head_time_ = frame.t_ns;
    head_ = std::move(frame);
  }

 private:
  void read_pending() {
    TimeNs t = 0;
    if (!rows_.next(5, &t, /*allow_equal=*/true)) {
      pending_.reset();
      return;
    }
    CsvReader& csv = rows_.csv();
    FeatureObservation obs;
    const std::int64_t cam = csv.get_int(1, "cam_id");
    if (calibrated_.count(static_cast<int>(cam)) == 0 || cam < 0 || cam > 1000) {
      csv.fail("column 2 'cam_id': camera " + std::to_string(cam) + " has no cam" + std::to_string(cam) +
               "/sensor.yaml");
    }
    obs.cam_id = static_cast<int>(cam);
    const std::int64_t id = csv.get_int(2, "feature_id");
    if (id < 0) csv.fail("column 3 'feature_id': negative id " + std::to_string(id));
    obs.feature_id = static_cast<std::uint64_t>(id);
    obs.uv = Eigen::Vector2d(csv.get_double(3, "u [px]"), csv.get_double(4, "v [px]"));
    pending_ = obs;
    pending_t_ = t;
  }

  TimedRows rows_;
  std::set<int> calibrated_;
  bool drop_;
  std::optional<FeatureObservation> pending_;
  TimeNs pending_t_ = 0;
};

}  // namespace

std::unique_ptr<Cursor> make_row_cursor(const std::filesystem::path& csv, const std::string& name,
                                        std::size_t columns, RowParser parser, const ReaderOptions& options,
                                        std::size_t alt_columns) {
  return std::make_unique<RowCursor>(csv, name, columns, alt_columns, std::move(parser), options);
}

std::unique_ptr<Cursor> make_camera_cursor(const std::filesystem::path& mav0, const std::vector<int>& cam_ids,
                                           const ReaderOptions& options) {
  return std::make_unique<CameraCursor>(mav0, cam_ids, options);
}

std::unique_ptr<Cursor> make_feature_cursor(const std::filesystem::path& csv, const std::set<int>& calibrated_cams,
                                            const ReaderOptions& options) {
  return std::make_unique<FeatureCursor>(csv, calibrated_cams, options);
}

}  // namespace vid::io::detail
