/// @file test_bad_inputs.cpp
/// @brief Each malformed input gives a DatasetError/ConfigError whose message names the file
/// and the line (or key) at fault; the drop/skip options count instead of failing.

#include <gtest/gtest.h>

#include "dataset_fixture.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

namespace fs = std::filesystem;

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    write_sequence(dir_.path(), kind_);
    mav0_ = dir_.path() / "mav0";
  }
  /// Replace line @p line (1-based) of @p rel with @p text.
  void set_line(const std::string& rel, std::size_t line, const std::string& text) {
    auto lines = read_lines(mav0_ / rel);
    ASSERT_LE(line, lines.size());
    lines[line - 1] = text;
    write_lines(mav0_ / rel, lines);
  }
  std::string line_of(const std::string& rel, std::size_t line) { return read_lines(mav0_ / rel).at(line - 1); }
  /// The error must name the file (path ending) and the location text.
  void expect_error(const std::string& file, const std::string& where, const std::string& what,
                    ReaderOptions o = {}) {
    const std::string msg = read_error(dir_.path(), o);
    ASSERT_FALSE(msg.empty()) << "no error for bad " << file;
    EXPECT_NE(msg.find((mav0_ / file).string() + where), std::string::npos)
        << "message does not name " << file << where << ": " << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << "message lacks '" << what << "': " << msg;
  }

  ScratchDir dir_;
  fs::path mav0_;
  SeqKind kind_ = SeqKind::kMono;
};

// 1. truncated row (the file ends in the middle of a row)
TEST_F(BadInput, TruncatedRow) {
  auto lines = read_lines(mav0_ / "imu0/data.csv");
  std::string text;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) text += lines[i] + "\n";
  text += lines.back().substr(0, lines.back().size() / 2);  // no newline, cut mid-row
  write_text(mav0_ / "imu0/data.csv", text);
  const std::string n = std::to_string(lines.size());
  const std::string msg = read_error(dir_.path());
  // Cut mid-number or at a comma: either a short row or a broken number, always at that line.
  EXPECT_NE(msg.find((mav0_ / "imu0/data.csv").string() + ":" + n + ":"), std::string::npos) << msg;
}

TEST_F(BadInput, TruncatedRowAtComma) {
  const std::string row = line_of("force0/data.csv", 5);
  set_line("force0/data.csv", 5, row.substr(0, row.rfind(',')));
  expect_error("force0/data.csv", ":5:", "expected 4 or 7 columns, got 3 (truncated row or missing column)");
}

// 2. text in a number field
TEST_F(BadInput, TextInNumberField) {
  std::string row = line_of("imu0/data.csv", 3);
  row = row.substr(0, row.find(',')) + ",0.1,0.2,0.3,abc,0.5,0.6";
  set_line("imu0/data.csv", 3, row);
  expect_error("imu0/data.csv", ":3:", "column 5 'a_RS_S_x [m s^-2]': expected a number, got 'abc'");
}

TEST_F(BadInput, TextInTimestamp) {
  set_line("mass0/data.csv", 2, "12x4,3.0");
  expect_error("mass0/data.csv", ":2:", "'timestamp [ns]': expected an integer, got '12x4'");
}

// 3. NaN and Inf
TEST_F(BadInput, NaNValue) {
  std::string row = line_of("state_groundtruth_estimate0/data.csv", 4);
  const std::size_t c = row.find(',');
  set_line("state_groundtruth_estimate0/data.csv", 4, row.substr(0, c) + ",nan" + row.substr(row.find(',', c + 1)));
  expect_error("state_groundtruth_estimate0/data.csv", ":4:", "non-finite value 'nan'");
}

TEST_F(BadInput, InfValue) {
  const std::string row = line_of("thrust0/data.csv", 6);
  set_line("thrust0/data.csv", 6, row.substr(0, row.find(',')) + ",inf");
  expect_error("thrust0/data.csv", ":6:", "non-finite value 'inf'");
}

// 4. missing column (every row of the file)
TEST_F(BadInput, MissingColumn) {
  auto lines = read_lines(mav0_ / "state_groundtruth_estimate0/data.csv");
  for (std::size_t i = 1; i < lines.size(); ++i) lines[i] = lines[i].substr(0, lines[i].rfind(','));
  write_lines(mav0_ / "state_groundtruth_estimate0/data.csv", lines);
  expect_error("state_groundtruth_estimate0/data.csv", ":2:", "expected 17 columns, got 16");
}

TEST_F(BadInput, Force0NeitherFourNorSevenColumns) {  // 4 = force only, 7 = force and its rate
  set_line("force0/data.csv", 2, line_of("force0/data.csv", 2) + ",1.0");
  expect_error("force0/data.csv", ":2:", "expected 4 or 7 columns, got 5");
}

TEST_F(BadInput, RotorColumnsDisagreeWithSensorYaml) {
  const std::string row = line_of("rotor0/data.csv", 2);
  set_line("rotor0/data.csv", 2, row + ",12.5");
  expect_error("rotor0/data.csv", ":2:", "expected 5 columns, got 6");
}

// 5. unsorted timestamps, 6. duplicate timestamp
TEST_F(BadInput, UnsortedTimestamps) {
  auto lines = read_lines(mav0_ / "imu0/data.csv");
  std::swap(lines[10], lines[11]);  // file lines 11 and 12
  write_lines(mav0_ / "imu0/data.csv", lines);
  expect_error("imu0/data.csv", ":12:", "timestamps not sorted");
}

TEST_F(BadInput, DuplicateTimestamp) {
  auto lines = read_lines(mav0_ / "force0/data.csv");
  const std::string t = lines[7].substr(0, lines[7].find(','));
  lines[8] = t + lines[8].substr(lines[8].find(','));  // line 9 repeats line 8's stamp
  write_lines(mav0_ / "force0/data.csv", lines);
  expect_error("force0/data.csv", ":9:", "duplicate timestamp " + t);
}

TEST_F(BadInput, DropBadTimestampsCountsInsteadOfFailing) {
  auto lines = read_lines(mav0_ / "imu0/data.csv");
  std::swap(lines[10], lines[11]);                         // one row out of order -> dropped
  lines.insert(lines.begin() + 20, lines[20]);             // one duplicate -> dropped
  write_lines(mav0_ / "imu0/data.csv", lines);
  ReaderOptions o;
  o.drop_bad_timestamps = true;
  DatasetReader reader(dir_.path(), o);
  TimeNs last = -1;
  std::size_t n = 0;
  while (auto m = reader.next()) {
    if (auto* s = std::get_if<ImuSample>(&*m)) {
      EXPECT_GT(s->t_ns, last);
      last = s->t_ns;
      ++n;
    }
  }
  for (const auto& s : reader.stats()) {
    if (s.name != "imu0") continue;
    EXPECT_EQ(s.dropped, 2u);
    EXPECT_EQ(s.dropped_bad_timestamps, 2u);
    EXPECT_EQ(s.count, n);
    EXPECT_EQ(n, 97u);  // 98 written + 1 duplicate - 2 dropped
  }
}

// 7. image file missing
TEST_F(BadInput, ImageFileMissing) {
  const std::string row = line_of("cam0/data.csv", 4);
  const std::string name = row.substr(row.find(',') + 1);
  fs::remove(mav0_ / "cam0" / "data" / name);
  expect_error("cam0/data.csv", ":4:", "image file missing: " + (mav0_ / "cam0" / "data" / name).string());
}

TEST_F(BadInput, SkipMissingImagesCounts) {
  const std::string row = line_of("cam0/data.csv", 4);
  fs::remove(mav0_ / "cam0" / "data" / row.substr(row.find(',') + 1));
  ReaderOptions o;
  o.skip_missing_images = true;
  DatasetReader reader(dir_.path(), o);
  std::size_t frames = 0;
  while (auto m = reader.next()) frames += std::holds_alternative<ImageFrame>(*m);
  EXPECT_EQ(frames, 9u);
  for (const auto& s : reader.stats()) {
    if (s.name == "cam0") {
      EXPECT_EQ(s.skipped_missing_images, 1u);
      EXPECT_EQ(s.dropped, 1u);
      EXPECT_EQ(s.count, 9u);
    }
  }
}

// 8. empty data.csv (header only, and zero bytes)
TEST_F(BadInput, EmptyDataCsv) {
  write_text(mav0_ / "force0/data.csv", "#timestamp [ns],f_x [N],f_y [N],f_z [N]\n");
  expect_error("force0/data.csv", ":", "no data rows");
  write_text(mav0_ / "imu0/data.csv", "");
  expect_error("imu0/data.csv", ":", "no data rows");
}

// 9. missing sensor.yaml / missing data file
TEST_F(BadInput, MissingCameraSensorYaml) {
  fs::remove(mav0_ / "cam0" / "sensor.yaml");
  expect_error("cam0/sensor.yaml", ":", "missing file (required for cam0/data.csv)");
}

TEST_F(BadInput, MissingRotorSensorYaml) {
  fs::remove(mav0_ / "rotor0" / "sensor.yaml");
  expect_error("rotor0/sensor.yaml", ":", "missing file");
}

TEST_F(BadInput, MissingImuData) {
  fs::remove(mav0_ / "imu0" / "data.csv");
  expect_error("imu0/data.csv", ":", "missing file");
}

// 10. unknown YAML key
TEST_F(BadInput, UnknownYamlKey) {
  write_text(mav0_ / "cam0/sensor.yaml", read_text(mav0_ / "cam0/sensor.yaml") + "focal_length: 400\n");
  const std::size_t n = read_lines(mav0_ / "cam0/sensor.yaml").size();
  expect_error("cam0/sensor.yaml", ":" + std::to_string(n) + ":", "unknown key 'focal_length'");
}

TEST_F(BadInput, UnknownNestedYamlKey) {
  std::string y = read_text(mav0_ / "imu0/sensor.yaml");
  y.replace(y.find("  rows: 4"), 9, "  rows: 4\n  colour: red");
  write_text(mav0_ / "imu0/sensor.yaml", y);
  expect_error("imu0/sensor.yaml", ":", "unknown key 'T_BS.colour'");
}

// 11. wrong YAML type
TEST_F(BadInput, WrongYamlType) {
  std::string y = read_text(mav0_ / "cam0/sensor.yaml");
  const std::size_t p = y.find("intrinsics:");
  y.replace(p, y.find('\n', p) - p, "intrinsics: fast");
  write_text(mav0_ / "cam0/sensor.yaml", y);
  expect_error("cam0/sensor.yaml", ":", "key 'intrinsics': expected a list of numbers, got 'fast'");
}

TEST_F(BadInput, WrongYamlTypeScalar) {
  write_text(mav0_ / "vehicle.yaml", "mass_kg: heavy\ngravity: 9.81\n");
  expect_error("vehicle.yaml", ":1:", "key 'mass_kg': expected a number, got 'heavy'");
}

// 12. negative rotor count
TEST_F(BadInput, NegativeRotorCount) {
  std::string y = read_text(mav0_ / "rotor0/sensor.yaml");
  y.replace(y.find("count: 4"), 8, "count: -4");
  write_text(mav0_ / "rotor0/sensor.yaml", y);
  expect_error("rotor0/sensor.yaml", ":3:", "key 'count': must be a positive number of rotors, got -4");
}

// More: YAML syntax, missing required key, inconsistent vehicle, bad transform, bad model.
TEST_F(BadInput, YamlSyntaxErrorHasLine) {
  write_text(mav0_ / "rotor0/sensor.yaml", "unit: rpm\ncount: [4\nrate_hz: 100\n");
  expect_error("rotor0/sensor.yaml", ":", "YAML syntax error");
}

TEST_F(BadInput, MissingRequiredYamlKey) {
  write_text(mav0_ / "rotor0/sensor.yaml", "sensor_type: rotor_speed\nunit: rpm\ncount: 4\n");
  expect_error("rotor0/sensor.yaml", ":", "missing required key 'rate_hz'");
}

TEST_F(BadInput, VehicleCoefficientsDisagreeWithRotorCount) {
  write_text(mav0_ / "vehicle.yaml", "mass_kg: 3\nrotor_thrust_coefficients: [1e-7, 1e-7, 1e-7]\n");
  expect_error("vehicle.yaml", ":", "key 'rotor_thrust_coefficients': 3 coefficients");
}

TEST_F(BadInput, NonRigidTransform) {
  std::string y = read_text(mav0_ / "imu0/sensor.yaml");
  const std::size_t p = y.find("data: [") + 7;
  y.replace(p, y.find(',', p) - p, "2");
  write_text(mav0_ / "imu0/sensor.yaml", y);
  expect_error("imu0/sensor.yaml", ":", "key 'T_BS': rotation part is not a rotation matrix");
}

TEST_F(BadInput, UnknownDistortionModel) {
  std::string y = read_text(mav0_ / "cam0/sensor.yaml");
  y.replace(y.find("radial-tangential"), 17, "fisheye");
  write_text(mav0_ / "cam0/sensor.yaml", y);
  expect_error("cam0/sensor.yaml", ":", "key 'distortion_model': expected radial-tangential, radtan or equidistant");
}

TEST_F(BadInput, QuaternionNotUnit) {
  const std::string row = line_of("state_groundtruth_estimate0/data.csv", 3);
  std::vector<std::string> f;
  std::stringstream ss(row);
  for (std::string s; std::getline(ss, s, ',');) f.push_back(s);
  f[4] = f[5] = f[6] = f[7] = "0";
  std::string out = f[0];
  for (std::size_t i = 1; i < f.size(); ++i) out += "," + f[i];
  set_line("state_groundtruth_estimate0/data.csv", 3, out);
  expect_error("state_groundtruth_estimate0/data.csv", ":3:", "quaternion q_RS is not unit length");
}

TEST(BadFolder, NotADatasetFolder) {
  ScratchDir dir;
  const std::string msg = read_error(dir.path());
  EXPECT_NE(msg.find(dir.path().string() + ": not a dataset folder"), std::string::npos) << msg;
  const std::string missing = read_error(dir.path() / "nope");
  EXPECT_NE(missing.find("nope: no such dataset folder"), std::string::npos) << missing;
}

class BadFeatures : public BadInput {
 protected:
  BadFeatures() { kind_ = SeqKind::kFeatures; }
};

TEST_F(BadFeatures, FeatureCameraWithoutCalibration) {
  fs::remove(mav0_ / "cam1" / "sensor.yaml");
  // The first cam1 observation is the second row of the first frame (file line 3).
  expect_error("feat0/data.csv", ":3:", "camera 1 has no cam1/sensor.yaml");
}

TEST_F(BadFeatures, DuplicateObservationInOneFrame) {
  set_line("feat0/data.csv", 4, line_of("feat0/data.csv", 2));
  expect_error("feat0/data.csv", ":4:", "duplicate observation of feature");
}

TEST_F(BadFeatures, FeatureRowsOutOfOrder) {
  auto lines = read_lines(mav0_ / "feat0/data.csv");
  std::swap(lines[6], lines[7]);  // last row of frame 1 <-> first row of frame 2
  write_lines(mav0_ / "feat0/data.csv", lines);
  expect_error("feat0/data.csv", ":8:", "timestamps not sorted");
}

TEST_F(BadFeatures, NoCameraCalibrationAtAll) {
  fs::remove(mav0_ / "cam0" / "sensor.yaml");
  fs::remove(mav0_ / "cam1" / "sensor.yaml");
  expect_error("cam0/sensor.yaml", ":", "missing file (required for feat0/data.csv)");
}

}  // namespace
}  // namespace vid::io::test
