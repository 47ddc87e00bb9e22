// LCM type conversions and checked decoding (io/include/io/lcm).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "io/errors.h"
#include "io/lcm/channels.h"
#include "io/lcm/lcm_convert.h"

namespace vid::lcm_io {
namespace {

TEST(LcmConvert, ImuRoundTripThroughBytes) {
  ImuSample s{1234567890123, Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(0.4, 9.81, -1.5)};
  const auto bytes = encode(to_lcm(s));
  const ImuSample r = from_lcm(decode<imu_t>(bytes.data(), bytes.size(), "IMU"), "IMU");
  EXPECT_EQ(r.t_ns, s.t_ns);
  EXPECT_EQ(r.gyro_I, s.gyro_I);
  EXPECT_EQ(r.accel_I, s.accel_I);
}

TEST(LcmConvert, RotorAndThrustRoundTrip) {
  RotorSample s{42, {5000.5, 5100.25, 4999.0, 5001.0}};
  const auto bytes = encode(to_lcm(s, "rpm"));
  const RotorSample r = from_lcm(decode<rotor_speeds_t>(bytes.data(), bytes.size(), "ROTORS"), "ROTORS", 4, "rpm");
  EXPECT_EQ(r.t_ns, 42);
  EXPECT_EQ(r.speeds, s.speeds);
  // The configured sensor disagrees: 6 rotors / rad/s.
  const auto m = decode<rotor_speeds_t>(bytes.data(), bytes.size(), "ROTORS");
  EXPECT_THROW(from_lcm(m, "ROTORS", 6, "rpm"), DecodeError);
  EXPECT_THROW(from_lcm(m, "ROTORS", 4, "rad/s"), DecodeError);

  const auto tb = encode(to_lcm(ThrustSample{7, 30.5}));
  const ThrustSample t = from_lcm(decode<thrust_t>(tb.data(), tb.size(), "THRUST"), "THRUST");
  EXPECT_EQ(t.t_ns, 7);
  EXPECT_EQ(t.thrust_N, 30.5);
}

TEST(LcmConvert, ImagePacksRowsAndValidates) {
  // 3x2 image stored with a row stride of 5 bytes: the message holds only the pixels.
  const std::uint8_t px[10] = {1, 2, 3, 99, 99, 4, 5, 6, 99, 99};
  const image_t m = make_image(100, 1, 3, 2, px, 5);
  EXPECT_EQ(m.encoding, "mono8");
  ASSERT_EQ(m.size, 6);
  EXPECT_EQ(m.data, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6}));
  EXPECT_NO_THROW(validate_image(m, "CAM1", 2));
  EXPECT_THROW(validate_image(m, "CAM1", 1), DecodeError);  // camera id out of range
  image_t bad = m;
  bad.width = 4;
  EXPECT_THROW(validate_image(bad, "CAM1", 2), DecodeError);  // size disagrees with width*height
  bad = m;
  bad.encoding = "rgb8";
  EXPECT_THROW(validate_image(bad, "CAM1", 2), DecodeError);
}

TEST(LcmConvert, MalformedPayloadsThrowNamingTheChannel) {
  const auto imu = encode(to_lcm(ImuSample{}));
  // Wrong type (fingerprint differs), truncated, garbage, empty.
  EXPECT_THROW(decode<rotor_speeds_t>(imu.data(), imu.size(), "ROTORS"), DecodeError);
  EXPECT_THROW(decode<imu_t>(imu.data(), imu.size() - 1, "IMU"), DecodeError);
  std::vector<std::uint8_t> junk(64, 0xAB);
  EXPECT_THROW(decode<image_t>(junk.data(), junk.size(), "CAM0"), DecodeError);
  EXPECT_THROW(decode<imu_t>(junk.data(), 0, "IMU"), DecodeError);
  try {
    decode<imu_t>(junk.data(), junk.size(), "MY_IMU");
    FAIL() << "no exception";
  } catch (const DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("MY_IMU"), std::string::npos) << e.what();
  }
  // An image whose size field claims more bytes than the payload holds.
  const std::uint8_t px[4] = {1, 2, 3, 4};
  auto bytes = encode(make_image(1, 0, 2, 2, px, 2));
  bytes.resize(bytes.size() - 2);
  EXPECT_THROW(decode<image_t>(bytes.data(), bytes.size(), "CAM0"), DecodeError);
}

TEST(LcmConvert, NonFiniteValuesAreRejected) {
  ImuSample s;
  s.gyro_I.x() = std::nan("");
  EXPECT_THROW(from_lcm(to_lcm(s), "IMU"), DecodeError);
  EXPECT_THROW(from_lcm(to_lcm(ThrustSample{1, INFINITY}), "THRUST"), DecodeError);
}

TEST(Channels, DefaultsAndYamlOverrides) {
  const ChannelNames d;
  EXPECT_EQ(d.imu, "IMU");
  EXPECT_EQ(d.state, "VID_STATE");
  const auto dir = std::filesystem::temp_directory_path() / ("vid_live_channels_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "ok.yaml") << "imu: DJI_IMU\ncam0: LEFT\nstate: EST\n";
    std::ofstream(dir / "bad.yaml") << "imu: X\ncamera0: LEFT\n";
  }
  const ChannelNames c = load_channels(dir / "ok.yaml");
  EXPECT_EQ(c.imu, "DJI_IMU");
  EXPECT_EQ(c.cam0, "LEFT");
  EXPECT_EQ(c.state, "EST");
  EXPECT_EQ(c.cam1, "CAM1");
  // Typed parameters: parse(print(x)) == x, and a changed name compares unequal.
  {
    std::ofstream(dir / "printed.yaml") << print(c);
  }
  EXPECT_TRUE(load_channels(dir / "printed.yaml") == c);
  EXPECT_FALSE(c == ChannelNames{});
  {
    std::ofstream(dir / "empty.yaml") << "";
  }
  EXPECT_TRUE(load_channels(dir / "empty.yaml") == ChannelNames{});
  try {
    load_channels(dir / "bad.yaml");
    FAIL() << "unknown key accepted";
  } catch (const io::ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("camera0"), std::string::npos) << what;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace vid::lcm_io
