/// @file test_image_decode.cpp
/// @brief decode_gray8 says why an image cannot be used (issue #28): missing, empty, not an
/// image, truncated or corrupt PNG, truncated JPEG; sound PNGs decode as cv::imread does.

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace vid
