/// @file test_csv_reader.cpp
/// @brief The streaming CSV cursor: headers/comments, CRLF, blanks after commas, line numbers.

#include <gtest/gtest.h>

#include <cmath>

#include "io/csv_reader.h"
#include "io/number_format.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

TEST(CsvReader, CrlfBlanksCommentsAndLastLineWithoutNewline) {
  ScratchDir dir;
  const auto p = dir.path() / "data.csv";
  write_text(p, "#timestamp, a [m], b\r\n1, 2.5 ,-3e-2\r\n\r\n# a comment\r\n2,\t+4,5");
  CsvReader csv(p);
  ASSERT_TRUE(csv.next_row());
  EXPECT_EQ(csv.line(), 2u);
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv.get_int(0, "t"), 1);
  EXPECT_EQ(csv.get_double(1, "a"), 2.5);
  EXPECT_EQ(csv.get_double(2, "b"), -3e-2);
  ASSERT_TRUE(csv.next_row());
  EXPECT_EQ(csv.line(), 5u);
  EXPECT_EQ(csv.get_double(1, "a"), 4.0);
  EXPECT_EQ(csv.get_double(2, "b"), 5.0);
  EXPECT_FALSE(csv.next_row());
  EXPECT_EQ(csv.bytes_read(), csv.bytes_total());
}

TEST(CsvReader, ErrorsNameFileLineAndColumn) {
  ScratchDir dir;
  const auto p = dir.path() / "x.csv";
  write_text(p, "1,2\n3,1.5.2\n4,-inf\n5,1e999\n");
  CsvReader csv(p);
  ASSERT_TRUE(csv.next_row());
  EXPECT_THROW(csv.expect_columns(3), DatasetError);
  ASSERT_TRUE(csv.next_row());
  try {
    csv.get_double(1, "value [m]");
    FAIL();
  } catch (const DatasetError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":2: column 2 'value [m]': expected a number, got '1.5.2'");
  }
  ASSERT_TRUE(csv.next_row());
  EXPECT_THROW(csv.get_double(1, "v"), DatasetError);
  ASSERT_TRUE(csv.next_row());
  EXPECT_THROW(csv.get_double(1, "v"), DatasetError);  // out of range
  EXPECT_THROW(csv.get_int(1, "v"), DatasetError);     // not an integer
}

TEST(CsvReader, MissingFileNamed) {
  try {
    CsvReader csv("/nonexistent/vid/data.csv");
    FAIL();
  } catch (const DatasetError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/vid/data.csv: missing file");
  }
}

TEST(NumberFormat, ShortestExactRoundTrip) {
  for (double v : {0.1, 1.0 / 3.0, -2.6890e-7, 1403636579.7585554, 5e-324, 1.7976931348623157e308, 0.0}) {
    const std::string s = format_double(v);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
  }
  EXPECT_EQ(format_double(0.1), "0.1");
  EXPECT_EQ(format_list({1.0, 2.5}), "[1, 2.5]");
}

TEST(CsvReader, HeaderRowNamedColumnsAndNonFinite) {
  ScratchDir dir;
  const auto p = dir.path() / "runs.csv";
  write_text(p, "name, t ,value\nloop,3,nan\n# comment\nsquare,4,x\n");
  CsvReader csv(p);
  csv.read_header({"name", "t", "value"});
  ASSERT_TRUE(csv.next_row());
  EXPECT_EQ(csv.field("name"), "loop");
  EXPECT_EQ(csv.get_int("t"), 3);
  EXPECT_TRUE(std::isnan(csv.get_double("value", CsvReader::NonFinite::kAccept)));
  try {
    csv.get_double("value");
    FAIL() << "NaN accepted";
  } catch (const DatasetError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":2: column 3 'value': non-finite value 'nan' (NaN/Inf)");
  }
  ASSERT_TRUE(csv.next_row());
  EXPECT_EQ(csv.line(), 4u);
  try {
    csv.get_double("value", CsvReader::NonFinite::kAccept);
    FAIL() << "text accepted";
  } catch (const DatasetError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":4: column 3 'value': expected a number, got 'x'");
  }
  EXPECT_THROW(csv.column("missing"), DatasetError);
  // A '#'-prefixed header is the same header; a different one names file:1 and both texts.
  write_text(p, "#name,t,value\n");
  CsvReader hashed(p);
  hashed.read_header({"name", "t", "value"});
  EXPECT_FALSE(hashed.next_row());
  write_text(p, "name,time\n");
  CsvReader bad(p);
  try {
    bad.read_header({"name", "t"});
    FAIL() << "bad header accepted";
  } catch (const DatasetError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":1: bad header 'name,time', expected 'name,t'");
  }
  write_text(p, "");
  CsvReader empty(p);
  EXPECT_THROW(empty.read_header({"name"}), DatasetError);
}

TEST(CsvReader, BlankSeparatedRows) {
  ScratchDir dir;
  const auto p = dir.path() / "traj.tum";
  write_text(p, "# t x y\n1.5  2\t3\n\n2 4 five\n");
  CsvReader csv(p, ' ');
  ASSERT_TRUE(csv.next_row());
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv.get_double(0, "t"), 1.5);
  EXPECT_EQ(csv.get_double(2, "y"), 3.0);
  ASSERT_TRUE(csv.next_row());
  EXPECT_EQ(csv.line(), 4u);
  EXPECT_THROW(csv.get_double(2, "y"), DatasetError);
  EXPECT_FALSE(csv.next_row());
}

}  // namespace
}  // namespace vid::io::test
