// ft_bridge: VID-Fusion's feature tracker (feature_tracker/src) behind a plain interface, doing
// what their feature_tracker_node does with each image (frequency control, first-image skip,
// id update, "publish" of the points tracked at least twice).
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Part of vidfusion_driver, which links VID-Fusion (GPL-3); the program as a whole is therefore
// GPL-3. A benchmark tool only, not part of the VID-MSCKF build (bench/peers/README.md).
#pragma once
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace vf {

struct TrackedPoint {
  int id;
  double x, y;    // undistorted normalized coordinates (z = 1)
  double u, v;    // pixel
  double vx, vy;  // normalized-coordinate velocity [1/s]
};

// Reads their parameters (max_cnt, min_dist, freq, F_threshold, equalize, fisheye, camera
// model) from config_file through their readParameters(), as their node does.
void tracker_init(const std::string &config_file, const std::string &vins_folder);
// One image (their img_callback). Returns true and fills out when their node would publish a
// feature message for this image (first image: no; first published: skipped, as theirs).
bool tracker_process(const cv::Mat &mono8, double t_s, std::vector<TrackedPoint> &out);
int tracker_max_cnt();
int tracker_freq();

}  // namespace vf
