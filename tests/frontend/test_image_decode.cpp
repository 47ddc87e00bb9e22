/// @file test_image_decode.cpp
/// @brief decode_gray8 says why an image cannot be used (issue #28): missing, empty, not an
/// image, truncated or corrupt PNG, truncated JPEG; sound PNGs decode as cv::imread does.
/// 10/12/16-bit camera data in 16-bit PNGs keeps its range (issue #25), and detect_bit_depth
/// finds the depth of a stream from samples (sBIT chunk, else the largest value).

#include <gtest/gtest.h>

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "frontend/image_decode.h"

namespace vid {
namespace {

namespace fs = std::filesystem;

std::string write(const std::string& name, const std::vector<unsigned char>& bytes) {
  const fs::path p = fs::path(::testing::TempDir()) / ("image_decode_" + name);
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                           static_cast<std::streamsize>(bytes.size()));
  return p.string();
}

std::vector<unsigned char> png() {
  cv::Mat img(48, 64, CV_8UC1);
  cv::randu(img, 0, 255);
  std::vector<unsigned char> out;
  cv::imencode(".png", img, out);
  return out;
}

std::string fault_of(const std::string& path) {
  std::string why;
  EXPECT_TRUE(decode_gray8(path, &why).empty()) << path;
  return why;
}

TEST(ImageDecode, SoundPngDecodesAsImread) {
  const std::string p = write("ok.png", png());
  std::string why;
  const cv::Mat a = decode_gray8(p, &why), b = cv::imread(p, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(why.empty());
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

TEST(ImageDecode, EachFaultIsNamed) {
  auto bytes = png();
  EXPECT_EQ(fault_of(write("none.png", {}).append(".missing")), "missing file (or not readable)");
  EXPECT_EQ(fault_of(write("empty.png", {})), "empty file");
  EXPECT_EQ(fault_of(write("text.png", {'h', 'e', 'l', 'l', 'o'})), "not a decodable image (PNG, JPEG, PGM, ...)");
  const std::vector<unsigned char> half(bytes.begin(), bytes.begin() + static_cast<long>(bytes.size() / 2));
  EXPECT_NE(fault_of(write("half.png", half)).find("truncated PNG (chunk IDAT at byte "), std::string::npos);
  const std::vector<unsigned char> no_end(bytes.begin(), bytes.end() - 12);  // without IEND
  EXPECT_EQ(fault_of(write("noend.png", no_end)), "truncated PNG (no IEND chunk in " +
                                                       std::to_string(no_end.size()) + " bytes)");
  auto flipped = bytes;
  flipped[40] ^= 0xFF;
  EXPECT_NE(fault_of(write("crc.png", flipped)).find("corrupt PNG (CRC mismatch in chunk"), std::string::npos);
  EXPECT_EQ(fault_of(write("cut.jpg", {0xFF, 0xD8, 0xFF, 0xE0, 0, 0})), "truncated JPEG (no end marker)");
}

/// A 16-bit image of a @p bits camera: values right-aligned, spanning 0 .. 2^bits - 1 (fixed seed).
cv::Mat camera16(int bits, double fraction_of_range = 1.0) {
  const int top = static_cast<int>(((1 << bits) - 1) * fraction_of_range);  // the largest value
  cv::Mat img(48, 64, CV_16UC1);
  cv::RNG rng(static_cast<std::uint64_t>(bits) * 7919u);
  rng.fill(img, cv::RNG::UNIFORM, 0, top);  // [0, top)
  img.at<std::uint16_t>(0, 0) = static_cast<std::uint16_t>(top);
  return img;
}

std::vector<unsigned char> encode(const cv::Mat& img) {
  std::vector<unsigned char> out;
  cv::imencode(".png", img, out);
  return out;
}

/// @p png with an sBIT chunk (gray: one byte) inserted after IHDR, CRC included.
std::vector<unsigned char> with_sbit(std::vector<unsigned char> png, unsigned char bits) {
  std::vector<unsigned char> chunk = {0, 0, 0, 1, 's', 'B', 'I', 'T', bits};
  const auto crc = static_cast<std::uint32_t>(crc32(0L, &chunk[4], 5));
  for (int k = 3; k >= 0; --k) chunk.push_back(static_cast<unsigned char>(crc >> (8 * k)));
  png.insert(png.begin() + 8 + 25, chunk.begin(), chunk.end());  // signature + IHDR (13 + 12)
  return png;
}

TEST(ImageDecode, RightAlignedSixteenBitKeepsItsRange) {
  for (int bits : {10, 12, 16}) {
    const cv::Mat raw = camera16(bits);
    const std::string p = write("depth" + std::to_string(bits) + ".png", encode(raw));
    const cv::Mat g = decode_gray8(p, nullptr, bits);
    ASSERT_EQ(g.type(), CV_8UC1) << bits;
    for (int i = 0; i < raw.rows; ++i)
      for (int j = 0; j < raw.cols; ++j) {
        // value / 2^(bits - 8), rounded to nearest (half to even) and saturated
        const auto want = cv::saturate_cast<std::uint8_t>(raw.at<std::uint16_t>(i, j) / double(1 << (bits - 8)));
        ASSERT_EQ(g.at<std::uint8_t>(i, j), want) << bits << " bits at " << i << "," << j;
      }
    double lo = 0, hi = 0;
    cv::minMaxLoc(g, &lo, &hi);
    EXPECT_GE(hi, 250.0) << bits << " bits: the camera's range must reach white";
    // the plain / 256 (the old decoding, still N = 16) leaves a 12-bit camera nearly black
    cv::minMaxLoc(decode_gray8(p), &lo, &hi);
    EXPECT_LE(hi, bits == 16 ? 255.0 : double(1 << (bits - 8)) + 0.5) << bits;
  }
}

TEST(ImageDecode, EightBitImagesIgnoreTheDepth) {
  const std::string p = write("eight.png", png());
  EXPECT_EQ(cv::norm(decode_gray8(p, nullptr, 12), cv::imread(p, cv::IMREAD_UNCHANGED), cv::NORM_INF), 0.0);
}

TEST(ImageDecode, ValuesAboveTheDepthSaturate) {
  cv::Mat raw(4, 4, CV_16UC1, cv::Scalar(5000));  // above 12 bits
  const std::string p = write("over.png", encode(raw));
  EXPECT_EQ(decode_gray8(p, nullptr, 12).at<std::uint8_t>(0, 0), 255);
}

TEST(ImageDecode, DetectBitDepthOfAStream) {
  auto depth = [](std::vector<std::pair<std::string, std::vector<unsigned char>>> files) {
    std::vector<std::string> paths;
    for (auto& [name, bytes] : files) paths.push_back(write(name, bytes));
    return detect_bit_depth(paths);
  };
  EXPECT_EQ(depth({{"d10.png", encode(camera16(10))}}).bits, 10);
  EXPECT_EQ(depth({{"d16.png", encode(camera16(16))}}).bits, 16);
  // A dark 12-bit frame (largest 1800: 11 bits) is still a 12-bit camera; with a bright one too.
  const BitDepth dark = depth({{"dark12.png", encode(camera16(12, 0.44))}});
  EXPECT_EQ(dark.bits, 12);
  EXPECT_EQ(dark.how, "largest 16-bit value 1801 in 1 sampled image");
  EXPECT_EQ(depth({{"dark12.png", encode(camera16(12, 0.44))}, {"bright12.png", encode(camera16(12))}}).bits, 12);
  // A 14-bit camera that says so in sBIT, although this frame's values would fit 10 bits.
  const BitDepth sbit = depth({{"sbit14.png", with_sbit(encode(camera16(10)), 14)}});
  EXPECT_EQ(sbit.bits, 14);
  EXPECT_EQ(sbit.how, "PNG sBIT chunk");
  EXPECT_FALSE(decode_gray8(write("sbit14b.png", with_sbit(encode(camera16(10)), 14)), nullptr, 14).empty());
  EXPECT_EQ(depth({{"eight2.png", png()}}).bits, 8);
  const BitDepth none = depth({{"broken.png", {'x'}}});
  EXPECT_EQ(none.bits, 16);
  EXPECT_EQ(none.how, "no readable image");
}

}  // namespace
}  // namespace vid
