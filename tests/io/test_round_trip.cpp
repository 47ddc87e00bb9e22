/// @file test_round_trip.cpp
/// @brief write -> read -> compare, exactly, for every stream of mono, stereo and
/// feature-level sequences; merge order, stats, calibration files, writer refusals.

#include <gtest/gtest.h>

#include <algorithm>

#include "dataset_fixture.h"
#include "io/dataset_reader.h"
#include "io/dataset_writer.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

// Exact (bit-for-bit) comparison of two measurements of the same type.
void expect_same(const Measurement& a, const Measurement& b, std::size_t i) {
  SCOPED_TRACE("measurement #" + std::to_string(i) + " at t=" + std::to_string(stamp_of(a)));
  ASSERT_EQ(a.index(), b.index());
  ASSERT_EQ(stamp_of(a), stamp_of(b));
  if (auto* x = std::get_if<ImuSample>(&a)) {
    const auto& y = std::get<ImuSample>(b);
    EXPECT_EQ(x->gyro_I, y.gyro_I);
    EXPECT_EQ(x->accel_I, y.accel_I);
  } else if (auto* x = std::get_if<RotorSample>(&a)) {
    EXPECT_EQ(x->speeds, std::get<RotorSample>(b).speeds);
  } else if (auto* x = std::get_if<ThrustSample>(&a)) {
    EXPECT_EQ(x->thrust_N, std::get<ThrustSample>(b).thrust_N);
  } else if (auto* x = std::get_if<ForceSample>(&a)) {
    const auto& y = std::get<ForceSample>(b);
    EXPECT_EQ(x->f_W_N, y.f_W_N);
    EXPECT_EQ(x->has_rate, y.has_rate);
    EXPECT_EQ(x->df_W_Nps, y.df_W_Nps);  // zero when the file has no rate columns
  } else if (auto* x = std::get_if<MassSample>(&a)) {
    EXPECT_EQ(x->mass_kg, std::get<MassSample>(b).mass_kg);
  } else if (auto* x = std::get_if<GroundTruthSample>(&a)) {
    const auto& y = std::get<GroundTruthSample>(b);
    EXPECT_EQ(x->T_WI.p, y.T_WI.p);
    EXPECT_EQ(x->T_WI.q.coeffs(), y.T_WI.q.coeffs());
    EXPECT_EQ(x->v_WI, y.v_WI);
    EXPECT_EQ(x->b_g, y.b_g);
    EXPECT_EQ(x->b_a, y.b_a);
  } else if (auto* x = std::get_if<ImageFrame>(&a)) {
    const auto& y = std::get<ImageFrame>(b);
    ASSERT_EQ(x->images.size(), y.images.size());
    for (std::size_t k = 0; k < x->images.size(); ++k) {
      EXPECT_EQ(x->images[k].cam_id, y.images[k].cam_id);
      EXPECT_EQ(x->images[k].path, y.images[k].path);
      EXPECT_TRUE(std::filesystem::path(y.images[k].path).is_absolute());
    }
  } else if (auto* x = std::get_if<FeatureFrame>(&a)) {
    const auto& y = std::get<FeatureFrame>(b);
    ASSERT_EQ(x->observations.size(), y.observations.size());
    for (std::size_t k = 0; k < x->observations.size(); ++k) {
      EXPECT_EQ(x->observations[k].cam_id, y.observations[k].cam_id);
      EXPECT_EQ(x->observations[k].feature_id, y.observations[k].feature_id);
      EXPECT_EQ(x->observations[k].uv, y.observations[k].uv);
      EXPECT_FALSE(y.observations[k].has_norm);
    }
  }
}

void expect_same_calib(const WrittenSequence& w, const DatasetCalibration& c) {
  ASSERT_EQ(c.cameras.size(), w.cameras.size());
  for (std::size_t i = 0; i < w.cameras.size(); ++i) {
    const CameraCalib& a = w.cameras[i];
    const CameraCalib& b = c.cameras[i];
    EXPECT_EQ(a.cam_id, b.cam_id);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.intrinsics, b.intrinsics);
    EXPECT_EQ(a.distortion, b.distortion);
    EXPECT_EQ(a.distortion_coeffs, b.distortion_coeffs);
    EXPECT_EQ(a.T_IC.matrix(), b.T_IC.matrix());
    EXPECT_EQ(a.timeshift_cam_imu_s, b.timeshift_cam_imu_s);
    EXPECT_EQ(a.rate_hz, b.rate_hz);
  }
  ASSERT_TRUE(c.imu.has_value());
  EXPECT_EQ(c.imu->gyro_noise_density, w.imu.gyro_noise_density);
  EXPECT_EQ(c.imu->gyro_random_walk, w.imu.gyro_random_walk);
  EXPECT_EQ(c.imu->accel_noise_density, w.imu.accel_noise_density);
  EXPECT_EQ(c.imu->accel_random_walk, w.imu.accel_random_walk);
  EXPECT_EQ(c.imu->rate_hz, w.imu.rate_hz);
  EXPECT_EQ(c.imu->T_BS.matrix(), w.imu.T_BS.matrix());
  ASSERT_TRUE(c.rotor.has_value());
  EXPECT_EQ(c.rotor->unit, w.rotor.unit);
  EXPECT_EQ(c.rotor->count, w.rotor.count);
  EXPECT_EQ(c.rotor->rate_hz, w.rotor.rate_hz);
  EXPECT_EQ(c.rotor->noise_density, w.rotor.noise_density);
  ASSERT_TRUE(c.vehicle.has_value());
  EXPECT_EQ(c.vehicle->mass_kg, w.vehicle.mass_kg);
  EXPECT_EQ(c.vehicle->gravity, w.vehicle.gravity);
  EXPECT_EQ(c.vehicle->rotor_thrust_coefficients, w.vehicle.rotor_thrust_coefficients);
}

void round_trip(SeqKind kind, bool open_mav0) {
  ScratchDir dir;
  const WrittenSequence w = write_sequence(dir.path(), kind);
  DatasetReader reader(open_mav0 ? dir.path() / "mav0" : dir.path());
  expect_same_calib(w, reader.calibration());
  std::size_t i = 0;
  while (auto m = reader.next()) {
    ASSERT_LT(i, w.expected.size()) << "reader returned more measurements than were written";
    expect_same(w.expected[i], *m, i);
    ++i;
  }
  EXPECT_EQ(i, w.expected.size());
  EXPECT_FALSE(reader.next().has_value()) << "next() after the end must stay empty";
  EXPECT_DOUBLE_EQ(reader.progress(), 1.0);
}

TEST(RoundTrip, MonoEveryStreamExact) { round_trip(SeqKind::kMono, false); }
TEST(RoundTrip, StereoEveryStreamExactFromMav0) { round_trip(SeqKind::kStereo, true); }
TEST(RoundTrip, FeatureLevelEveryStreamExact) { round_trip(SeqKind::kFeatures, false); }

TEST(RoundTrip, FeatureFolderHasNoCameraDataButCalibration) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kFeatures);
  const auto mav0 = dir.path() / "mav0";
  EXPECT_TRUE(std::filesystem::exists(mav0 / "cam1" / "sensor.yaml"));
  EXPECT_FALSE(std::filesystem::exists(mav0 / "cam0" / "data.csv"));
  DatasetReader reader(dir.path());
  EXPECT_TRUE(reader.has_stream("feat0"));
  EXPECT_FALSE(reader.has_stream("cam0"));
  EXPECT_EQ(reader.calibration().cameras.size(), 2u);
}

TEST(RoundTrip, StereoGroupsEqualTimestampsIntoOneFrame) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kStereo);
  DatasetReader reader(dir.path());
  std::size_t stereo = 0, single = 0;
  while (auto m = reader.next()) {
    if (auto* f = std::get_if<ImageFrame>(&*m)) {
      if (f->images.size() == 2) {
        EXPECT_EQ(f->images[0].cam_id, 0);
        EXPECT_EQ(f->images[1].cam_id, 1);
        ++stereo;
      } else {
        ASSERT_EQ(f->images.size(), 1u);
        EXPECT_EQ(f->images[0].cam_id, 1);
        ++single;
      }
    }
  }
  EXPECT_EQ(stereo, 10u);
  EXPECT_EQ(single, 1u);
}

TEST(RoundTrip, StatsCountSpanAndLargestGap) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kStereo);
  DatasetReader reader(dir.path());
  while (reader.next()) {
  }
  const TimeNs t0 = 1403636579758555392;
  bool seen_imu = false, seen_cam1 = false;
  for (const StreamStats& s : reader.stats()) {
    EXPECT_EQ(s.dropped, 0u) << s.name;
    if (s.name == "imu0") {
      seen_imu = true;
      EXPECT_EQ(s.count, 98u);
      EXPECT_EQ(s.first_ns, t0);
      EXPECT_EQ(s.last_ns, t0 + 99 * 5'000'000);
      EXPECT_EQ(s.largest_gap_ns, 15'000'000);
      EXPECT_EQ(s.largest_gap_at_ns, t0 + 39 * 5'000'000);
    }
    if (s.name == "cam1") {
      seen_cam1 = true;
      EXPECT_EQ(s.count, 11u);
    }
  }
  EXPECT_TRUE(seen_imu);
  EXPECT_TRUE(seen_cam1);
}

TEST(RoundTrip, OptionsSkipImagesFeaturesAndGroundTruth) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kMono);
  ReaderOptions o;
  o.read_images = false;
  o.read_groundtruth = false;
  DatasetReader reader(dir.path(), o);
  while (auto m = reader.next()) {
    EXPECT_FALSE(std::holds_alternative<ImageFrame>(*m));
    EXPECT_FALSE(std::holds_alternative<GroundTruthSample>(*m));
    EXPECT_FALSE(std::holds_alternative<ForceSample>(*m));
    EXPECT_FALSE(std::holds_alternative<MassSample>(*m));
  }
  EXPECT_TRUE(reader.has_stream("cam0"));  // present in the folder, just not read
}

TEST(RoundTrip, ReaderNeverDecodesImages) {
  ScratchDir dir;
  write_sequence(dir.path(), SeqKind::kMono);
  // Replace every PNG with bytes no decoder accepts: the reader only checks existence.
  std::size_t replaced = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path() / "mav0/cam0/data")) {
    write_text(e.path(), "not a png");
    ++replaced;
  }
  ASSERT_EQ(replaced, 10u);
  DatasetReader reader(dir.path());
  std::size_t frames = 0;
  while (auto m = reader.next()) frames += std::holds_alternative<ImageFrame>(*m);
  EXPECT_EQ(frames, 10u);
}

TEST(Writer, RefusesUnsortedTimestampsNonFiniteValuesAndColourImages) {
  ScratchDir dir;
  DatasetWriter w(dir.path());
  w.write(ImuSample{100, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  try {
    w.write(ImuSample{100, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
    FAIL() << "duplicate timestamp accepted";
  } catch (const DatasetError& e) {
    EXPECT_NE(std::string(e.what()).find("imu0/data.csv"), std::string::npos) << e.what();
  }
  EXPECT_THROW(w.write(ForceSample{5, Eigen::Vector3d(0, std::nan(""), 0)}), DatasetError);
  EXPECT_THROW(w.write_image(0, 7, cv::Mat(4, 4, CV_8UC3)), DatasetError);
  EXPECT_THROW(w.write(RotorSample{9, {}}), DatasetError);
  w.write(RotorSample{10, {1.0, 2.0}});
  EXPECT_THROW(w.write(RotorSample{11, {1.0, 2.0, 3.0}}), DatasetError);
  w.close();
  EXPECT_THROW(w.write(MassSample{20, 1.0}), DatasetError);
}

TEST(RoundTrip, Force0WithAndWithoutRateColumns) {
  // Old 4-column files read with has_rate false and a zero rate; the 7-column ones exactly.
  for (const bool with_rate : {false, true}) {
    SCOPED_TRACE(with_rate ? "7 columns" : "4 columns");
    ScratchDir dir(with_rate ? "_7" : "_4");
    {
      DatasetWriter w(dir.path());
      w.write(ImuSample{1, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
      ForceSample f{1, Eigen::Vector3d(1.5, -2.25, 3.125)};
      f.has_rate = with_rate;
      if (with_rate) f.df_W_Nps = Eigen::Vector3d(-1e-3, 250.5, 1.0 / 3.0);
      w.write(f);
    }
    const auto lines = read_lines(dir.path() / "mav0" / "force0" / "data.csv");
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(std::count(lines[0].begin(), lines[0].end(), ','), with_rate ? 6 : 3) << lines[0];
    EXPECT_EQ(lines[0].find("dFx/dt [N s^-1]") != std::string::npos, with_rate) << lines[0];
    DatasetReader reader(dir.path());
    bool seen = false;
    while (auto m = reader.next()) {
      if (const auto* f = std::get_if<ForceSample>(&*m)) {
        seen = true;
        EXPECT_EQ(f->f_W_N, Eigen::Vector3d(1.5, -2.25, 3.125));
        EXPECT_EQ(f->has_rate, with_rate);
        EXPECT_EQ(f->df_W_Nps, with_rate ? Eigen::Vector3d(-1e-3, 250.5, 1.0 / 3.0) : Eigen::Vector3d::Zero());
      }
    }
    EXPECT_TRUE(seen);
  }
}

TEST(Writer, RefusesForceRowsThatMixRateAndNoRate) {
  ScratchDir dir;
  DatasetWriter w(dir.path());
  w.write(ForceSample{1, Eigen::Vector3d::Ones()});
  ForceSample with_rate{2, Eigen::Vector3d::Ones(), Eigen::Vector3d::Ones(), true};
  EXPECT_THROW(w.write(with_rate), DatasetError);
}

TEST(Writer, FlushesRowsAsItGoes) {
  ScratchDir dir;
  DatasetWriter w(dir.path());
  w.write(ImuSample{1, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6)});
  // Not closed yet: the row must already be on disk.
  const auto lines = read_lines(dir.path() / "mav0" / "imu0" / "data.csv");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1], "1,1,2,3,4,5,6");
}

}  // namespace
}  // namespace vid::io::test
