/// @file csv_fuzz.cpp
/// @brief libFuzzer target of vid::io::CsvReader (io/src/csv_reader.cpp): every way a reader
/// walks a file (plain rows, a required header with named columns, blank-separated TUM rows).
/// Only io::DatasetError is an expected outcome; any other exception or sanitizer report is a bug.
///
/// Input: byte 0 picks the mode (bit 0: blank separator, bit 1: header row, bit 2: accept
/// NaN/Inf); the rest is the file.

#include <string_view>

#include "fuzz_util.h"
#include "io/csv_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  const auto path = vid::fuzz::scratch_dir() / "data.csv";
  vid::fuzz::write_file(path, std::string_view(reinterpret_cast<const char*>(data + 1), size - 1));
  using vid::io::CsvReader;
  const auto non_finite = (mode & 4) ? CsvReader::NonFinite::kAccept : CsvReader::NonFinite::kReject;
  try {
    CsvReader csv(path, (mode & 1) ? ' ' : ',');
    if (mode & 2) csv.read_header({"t", "x", "y"});
    while (csv.next_row()) {
      if (mode & 2) {  // named columns, as the header-row readers use them
        csv.expect_columns(3);
        (void)csv.get_int("t");
        (void)csv.get_double("x", non_finite);
        (void)csv.field("y");
        continue;
      }
      csv.expect_columns(csv.size() < 4 ? 3 : 4, 7);
      (void)csv.get_int(0, "timestamp");
      for (std::size_t i = 1; i < csv.size(); ++i) (void)csv.get_double(i, "value", non_finite);
      (void)csv.where();
    }
    (void)csv.bytes_read();
  } catch (const vid::io::DatasetError&) {
  }
  return 0;
}
