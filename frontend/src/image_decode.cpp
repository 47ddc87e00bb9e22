/// @file image_decode.cpp
/// @brief Image files -> 8-bit gray (shared by vid_run and vid_replay).
#include "frontend/image_decode.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace vid {

cv::Mat decode_gray8(const std::string& path) {
  cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (img.empty()) return img;
  if (img.depth() == CV_16U) img.convertTo(img, CV_8U, 1.0 / 256.0);
  if (img.depth() != CV_8U) return {};
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2GRAY);
  return img;
}

}  // namespace vid
