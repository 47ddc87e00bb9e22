// Inputs the fuzz targets (fuzz/, issue #26) found crashing, each kept as a regression test:
// the exact bytes the fuzzer wrote, and the same fault on an otherwise valid message.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/lcm/lcm_convert.h"

namespace vid::lcm_io {
namespace {

/// The DecodeError message of decoding @p bytes as T, or "" when it decodes.
template <class T>
std::string decode_error(const std::vector<std::uint8_t>& bytes) {
  try {
    (void)decode<T>(bytes.data(), bytes.size(), "CAM0");
  } catch (const DecodeError& e) {
    return e.what();
  }
  return "";
}

void put_be32(std::vector<std::uint8_t>* b, std::size_t at, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) (*b)[at + i] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
}

std::vector<std::uint8_t> small_image() {
  const std::uint8_t pixels[6] = {1, 2, 3, 4, 5, 6};
  return encode(make_image(100, 0, 3, 2, pixels, 3));
}

// fuzz_lcm: an image_t whose size field claims 1.7e9 bytes made lcm-gen's decoder allocate
// and zero 1.7 GB for a 52-byte payload (libFuzzer: out-of-memory).
TEST(FuzzRegressions, ImageSizeBeyondPayloadIsRejectedBeforeAllocating) {
  const std::vector<std::uint8_t> crash = {
      0x16, 0xba, 0x1e, 0x34, 0x49, 0xf6, 0x24, 0x77, 0x00, 0x24, 0x77, 0x1b, 0x01,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x28, 0x40, 0x3e, 0x00, 0xfd,
      0xbe, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x65, 0x90, 0x00, 0x00, 0x40, 0x74,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x28, 0x40, 0x3e, 0x00, 0x00, 0x00, 0x00};
  EXPECT_NE(decode_error<image_t>(crash).find("exceeds the payload"), std::string::npos) << decode_error<image_t>(crash);

  std::vector<std::uint8_t> img = small_image();
  ASSERT_EQ(decode_error<image_t>(img), "");
  // fingerprint 8, timestamp 8, camera_id/width/height 12, encoding 4 + "mono8\0", then size
  put_be32(&img, 8 + 8 + 12 + 4 + 6, 2'000'000'000);
  EXPECT_EQ(decode_error<image_t>(img),
            "CAM0: payload of " + std::to_string(img.size()) +
                " bytes does not decode as image_t: size 2000000000 exceeds the payload");
}

// fuzz_lcm: a string length of INT32_MIN passed lcm-gen's bounds check (it only tests
// len > remaining) and then overflowed in len - 1 (UBSan: signed integer overflow), which in a
// plain build wraps to a 2 GB read past the buffer.
TEST(FuzzRegressions, NegativeStringLengthIsRejected) {
  const std::vector<std::uint8_t> crash = {
      0x16, 0xba, 0x1e, 0x34, 0x49, 0xf6, 0x24, 0x77, 0x00, 0x24, 0x77, 0x1b, 0x01,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x28, 0x00, 0x40, 0x82, 0x00, 0x00, 0x3e, 0x00,
      0xfd, 0x00, 0x80, 0x00, 0x00, 0x00, 0x0a, 0x10, 0x00, 0x00, 0x00};
  EXPECT_NE(decode_error<image_t>(crash).find("encoding: string length -2147483648"), std::string::npos)
      << decode_error<image_t>(crash);

  std::vector<std::uint8_t> img = small_image();
  put_be32(&img, 8 + 8 + 12, 0);  // a string's length counts its NUL: 0 is impossible
  EXPECT_NE(decode_error<image_t>(img).find("encoding: string length 0"), std::string::npos);
}

// The same check on the other types with length fields.
TEST(FuzzRegressions, RotorAndStatusLengthsBeyondPayloadAreRejected) {
  std::vector<std::uint8_t> rotor = encode(to_lcm(RotorSample{1, {1.0, 2.0, 3.0, 4.0}}, "rpm"));
  ASSERT_EQ(decode_error<rotor_speeds_t>(rotor), "");
  put_be32(&rotor, 16, 1'000'000'000);
  EXPECT_NE(decode_error<rotor_speeds_t>(rotor).find("count 1000000000 exceeds the payload"), std::string::npos);

  status_t st;
  st.status_text = "tracking";
  st.num_counters = 1;
  st.counter_names = {"imu_duplicate"};
  st.counter_values = {3};
  std::vector<std::uint8_t> status = encode(st);
  ASSERT_EQ(decode_error<status_t>(status), "");
  // fingerprint 8, timestamp 8, status 1, three strings (4 + length each), reinit_count 4
  const std::size_t n_at = 8 + 8 + 1 + (4 + 9) + (4 + 1) + (4 + 1) + 4;
  put_be32(&status, n_at, 400'000'000);
  EXPECT_NE(decode_error<status_t>(status).find("num_counters 400000000 exceeds the payload"), std::string::npos);
  put_be32(&status, n_at, 1);
  put_be32(&status, n_at + 4, -7);  // the counter's name
  EXPECT_NE(decode_error<status_t>(status).find("counter_names: string length -7"), std::string::npos);
}

}  // namespace
}  // namespace vid::lcm_io
