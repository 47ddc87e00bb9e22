#pragma once
/// @file csv_reader.h
/// @brief Streaming reader of one EuRoC-style CSV file: one row in memory at a time,
/// '#' header/comment lines skipped, CRLF and blanks after commas accepted, every error
/// reported as "FILE:LINE: message" (DatasetError). The one CSV reader of the project: also
/// reads files with a required header row (named columns) and blank-separated files (TUM).

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/errors.h"

namespace vid::io {

/// @brief Cursor over the data rows of a CSV file.
class CsvReader {
 public:
  /// @brief How a value that parses as NaN/Inf is treated by get_double.
  enum class NonFinite { kReject, kAccept };

  /// @brief Open @p path; throws DatasetError naming the file if it cannot be opened.
  /// @p separator ' ' splits on any run of blanks (TUM trajectories) instead of one character.
  explicit CsvReader(const std::filesystem::path& path, char separator = ',');

  /// @brief Read the first line as a header row (a leading '#' is optional) and require the
  /// column names @p expected ("FILE:1: bad header 'x', expected 'a,b'"); call before next_row().
  /// Named columns then resolve through column().
  void read_header(const std::vector<std::string>& expected);
  /// @brief Index of header column @p name (throws if the header has no such column).
  std::size_t column(std::string_view name) const;

  /// @brief Advance to the next data row; false at end of file.
  bool next_row();

  /// @brief Number of fields of the current row.
  std::size_t size() const { return fields_.size(); }
  /// @brief Field @p i of the current row, trimmed of blanks.
  std::string_view field(std::size_t i) const { return fields_.at(i); }
  /// @brief 1-based line number of the current row.
  std::size_t line() const { return line_; }
  /// @brief Bytes consumed so far (for progress).
  std::uint64_t bytes_read() const { return bytes_read_; }
  /// @brief Total file size in bytes.
  std::uint64_t bytes_total() const { return bytes_total_; }
  const std::filesystem::path& path() const { return path_; }
  /// @brief Number of data rows returned so far.
  std::size_t rows() const { return rows_; }

  /// @brief Throw unless the row has exactly @p n fields ("expected n columns, got m").
  void expect_columns(std::size_t n) const;
  /// @brief Throw unless the row has @p n or @p alt fields (a stream with optional columns).
  void expect_columns(std::size_t n, std::size_t alt) const;
  /// @brief Field @p i as an integer (timestamps, ids); throws naming file:line and column.
  std::int64_t get_int(std::size_t i, std::string_view column) const;
  /// @brief Field @p i as a double; text, and NaN/Inf unless @p non_finite is kAccept, throw
  /// naming file:line and column.
  double get_double(std::size_t i, std::string_view column, NonFinite non_finite = NonFinite::kReject) const;
  /// @brief Named-column forms (after read_header): the column name is the message's column.
  std::int64_t get_int(std::string_view name) const { return get_int(column(name), name); }
  double get_double(std::string_view name, NonFinite non_finite = NonFinite::kReject) const {
    return get_double(column(name), name, non_finite);
  }
  std::string_view field(std::string_view name) const { return field(column(name)); }

  /// @brief Throw DatasetError "FILE:LINE: message" at the current row.
  [[noreturn]] void fail(const std::string& message) const;
  /// @brief "FILE:LINE" of the current row.
  std::string where() const;

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  std::string buf_;
  std::vector<std::string_view> fields_;
  std::vector<std::string> header_;
  char separator_ = ',';
  std::size_t line_ = 0;
  std::size_t rows_ = 0;
  std::uint64_t bytes_read_ = 0;
  std::uint64_t bytes_total_ = 0;
};

}  // namespace vid::io
