/// @file image_decode.cpp
/// @brief Image files -> 8-bit gray (shared by vid_run, vid_replay and vid_track).
#include "frontend/image_decode.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace vid {

namespace {

std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

/// Walk a PNG's chunks up to IEND; empty when sound, else what is wrong.
std::string png_fault(const std::vector<unsigned char>& b) {
  const std::size_t n = b.size();
  std::size_t at = 8;  // after the signature
  while (at + 12 <= n) {
    const std::size_t len = be32(&b[at]);
    std::string type(reinterpret_cast<const char*>(&b[at + 4]), 4);
    for (char& c : type)
      if (!std::isalpha(static_cast<unsigned char>(c))) c = '?';  // a corrupt type: keep the message printable
    if (len > n || at + 12 + len > n)
      return "truncated PNG (chunk " + type + " at byte " + std::to_string(at) + " runs past the end of the " +
             std::to_string(n) + "-byte file)";
    const auto crc = static_cast<std::uint32_t>(crc32(0L, &b[at + 4], static_cast<uInt>(len + 4)));
    if (crc != be32(&b[at + 8 + len]))
      return "corrupt PNG (CRC mismatch in chunk " + type + " at byte " + std::to_string(at) + ")";
    if (type == "IEND") return {};
    at += 12 + len;
  }
  return "truncated PNG (no IEND chunk in " + std::to_string(n) + " bytes)";
}

/// The sBIT chunk of a sound PNG (its largest entry: gray has one, RGB three), or 0 without one.
int png_sbit(const std::vector<unsigned char>& b) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() < 8 || std::memcmp(b.data(), kPng, 8) != 0) return 0;
  for (std::size_t at = 8; at + 12 <= b.size();) {
    const std::size_t len = be32(&b[at]);
    if (at + 12 + len > b.size()) return 0;
    const std::string type(reinterpret_cast<const char*>(&b[at + 4]), 4);
    if (type == "sBIT") return len ? *std::max_element(&b[at + 8], &b[at + 8] + len) : 0;
    if (type == "IDAT" || type == "IEND") return 0;  // sBIT comes before the image data
    at += 12 + len;
  }
  return 0;
}

/// Read a whole file; empty with @p why set when it cannot be read.
std::vector<unsigned char> read_file(const std::string& path, std::string* why) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    *why = std::ifstream(path).good() ? "cannot open" : "missing file (or not readable)";
    return {};
  }
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) *why = "read error";
  return bytes;
}

/// Structure check by format; empty when the bytes may go to the decoder.
std::string structure_fault(const std::vector<unsigned char>& b) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.empty()) return "empty file";
  if (b.size() >= 8 && std::memcmp(b.data(), kPng, 8) == 0) return png_fault(b);
  if (b.size() >= 2 && b[0] == 0xFF && b[1] == 0xD8) {
    if (b.size() < 4 || b[b.size() - 2] != 0xFF || b[b.size() - 1] != 0xD9) return "truncated JPEG (no end marker)";
    return {};
  }
  return {};  // another format: OpenCV decides (its other decoders do not print)
}

}  // namespace

cv::Mat decode_gray8(const std::string& path, std::string* fault, int significant_bits) {
  auto fail = [&](std::string why) {
    if (fault) *fault = std::move(why);
    return cv::Mat();
  };
  std::string why;
  const std::vector<unsigned char> bytes = read_file(path, &why);
  if (!why.empty()) return fail(why);
  if (why = structure_fault(bytes); !why.empty()) return fail(why);
  cv::Mat img = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  if (img.empty()) return fail("not a decodable image (PNG, JPEG, PGM, ...)");
  if (img.depth() == CV_16U) {
    const int bits = std::clamp(significant_bits, 9, 16);
    img.convertTo(img, CV_8U, 1.0 / static_cast<double>(1 << (bits - 8)));  // rounds, saturates
  }
  if (img.depth() != CV_8U) return fail("unsupported pixel depth (8- or 16-bit expected)");
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2GRAY);
  return img;
}

BitDepth detect_bit_depth(const std::vector<std::string>& paths) {
  int sbit = 0, eight = 0, sixteen = 0;
  double largest = 0.0;
  for (const auto& path : paths) {
    std::string why;
    const std::vector<unsigned char> bytes = read_file(path, &why);
    if (!why.empty() || !structure_fault(bytes).empty()) continue;
    const cv::Mat img = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
    if (img.empty()) continue;
    if (img.depth() != CV_16U) {
      ++eight;
      continue;
    }
    ++sixteen;
    sbit = std::max(sbit, png_sbit(bytes));
    double lo = 0.0, hi = 0.0;
    cv::minMaxLoc(img.reshape(1), &lo, &hi);
    largest = std::max(largest, hi);
  }
  if (sixteen == 0)
    return eight ? BitDepth{8, "8-bit images"} : BitDepth{16, "no readable image"};
  if (sbit >= 9 && sbit <= 16) return {sbit, "PNG sBIT chunk"};
  int length = 0;  // bit length of the largest value
  while (length < 16 && largest >= static_cast<double>(1 << length)) ++length;
  const int bits = std::max(10, length + (length % 2));  // 10, 12, 14 or 16
  return {bits, "largest 16-bit value " + std::to_string(static_cast<int>(largest)) + " in " +
                    std::to_string(sixteen) + " sampled image" + (sixteen > 1 ? "s" : "")};
}

}  // namespace vid
