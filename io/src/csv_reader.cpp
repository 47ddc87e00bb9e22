#include "io/csv_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace vid::io {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

}  // namespace

CsvReader::CsvReader(const std::filesystem::path& path, char separator) : path_(path), separator_(separator) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw DatasetError(path.string() + ": missing file");
  }
  in_.open(path, std::ios::binary);
  if (!in_) throw DatasetError(path.string() + ": cannot open file");
  bytes_total_ = std::filesystem::file_size(path, ec);
}

bool CsvReader::next_row() {
  while (std::getline(in_, buf_)) {
    ++line_;
    bytes_read_ += buf_.size() + 1;
    std::string_view row = trim(buf_);
    if (row.empty() || row.front() == '#') continue;  // blank line, header or comment
    fields_.clear();
    if (separator_ == ' ') {  // any run of blanks separates
      while (!row.empty()) {
        std::size_t end = 0;
        while (end < row.size() && !is_blank(row[end])) ++end;
        fields_.push_back(row.substr(0, end));
        row = trim(row.substr(end));
      }
      ++rows_;
      return true;
    }
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = row.find(separator_, start);
      if (comma == std::string_view::npos) {
        fields_.push_back(trim(row.substr(start)));
        break;
      }
      fields_.push_back(trim(row.substr(start, comma - start)));
      start = comma + 1;
    }
    ++rows_;
    return true;
  }
  bytes_read_ = bytes_total_;
  return false;
}

void CsvReader::read_header(const std::vector<std::string>& expected) {
  std::string joined;
  for (const std::string& name : expected) joined += (joined.empty() ? "" : ",") + name;
  if (line_ != 0 || !std::getline(in_, buf_)) {
    line_ = 1;
    fail("empty file, expected header '" + joined + "'");
  }
  ++line_;
  bytes_read_ += buf_.size() + 1;
  std::string_view row = trim(buf_);
  if (!row.empty() && row.front() == '#') row.remove_prefix(1);
  header_.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t sep = row.find(separator_, start);
    header_.emplace_back(trim(row.substr(start, sep == std::string_view::npos ? sep : sep - start)));
    if (sep == std::string_view::npos) break;
    start = sep + 1;
  }
  if (header_ != expected) fail("bad header '" + std::string(row) + "', expected '" + joined + "'");
}

std::size_t CsvReader::column(std::string_view name) const {
  for (std::size_t i = 0; i < header_.size(); ++i) {
    if (header_[i] == name) return i;
  }
  throw DatasetError(path_.string() + ": no column '" + std::string(name) + "' in the header");
}

std::string CsvReader::where() const { return path_.string() + ":" + std::to_string(line_); }

void CsvReader::fail(const std::string& message) const { throw DatasetError(where() + ": " + message); }

void CsvReader::expect_columns(std::size_t n) const {
  if (fields_.size() != n) {
    fail("expected " + std::to_string(n) + " columns, got " + std::to_string(fields_.size()) +
         (fields_.size() < n ? " (truncated row or missing column)" : ""));
  }
}

void CsvReader::expect_columns(std::size_t n, std::size_t alt) const {
  if (alt == n || alt == 0) return expect_columns(n);
  if (fields_.size() != n && fields_.size() != alt) {
    fail("expected " + std::to_string(n) + " or " + std::to_string(alt) + " columns, got " +
         std::to_string(fields_.size()) +
         (fields_.size() < std::min(n, alt) ? " (truncated row or missing column)" : ""));
  }
}

std::int64_t CsvReader::get_int(std::size_t i, std::string_view column) const {
  const std::string_view f = field(i);
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (f.empty() || ec != std::errc() || ptr != f.data() + f.size()) {
    fail("column " + std::to_string(i + 1) + " '" + std::string(column) +
         "': expected an integer, got '" + std::string(f) + "'");
  }
  return v;
}

double CsvReader::get_double(std::size_t i, std::string_view column, NonFinite non_finite) const {
  std::string_view f = field(i);
  if (!f.empty() && f.front() == '+') f.remove_prefix(1);  // from_chars rejects a leading '+'
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (f.empty() || ec != std::errc() || ptr != f.data() + f.size()) {
    fail("column " + std::to_string(i + 1) + " '" + std::string(column) +
         "': expected a number, got '" + std::string(field(i)) + "'");
  }
  if (!std::isfinite(v) && non_finite == NonFinite::kReject) {
    fail("column " + std::to_string(i + 1) + " '" + std::string(column) + "': non-finite value '" +
         std::string(f) + "' (NaN/Inf)");
  }
  return v;
}

}  // namespace vid::io
