// ft_bridge: see ft_bridge.h. Compiled in vf_feature_tracker with their tracker's globals renamed
// (CMakeLists.txt), so that it sees the tracker's ROW/COL/readParameters.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Part of vidfusion_driver, which links VID-Fusion (GPL-3); the program as a whole is therefore
// GPL-3. A benchmark tool only, not part of the VID-MSCKF build (bench/peers/README.md).
#include "ft_bridge.h"

#include <cmath>
#include <cstdlib>

#include "feature_tracker.h"

namespace {
FeatureTracker tracker_data[NUM_OF_CAM];
double first_image_time = 0;
int pub_count = 1;
bool first_image_flag = true;
double last_image_time = 0;
bool init_pub = false;
}  // namespace

namespace vf {

void tracker_init(const std::string &config_file, const std::string &vins_folder) {
  ros::NodeHandle::set("config_file", config_file);
  ros::NodeHandle::set("vins_folder", vins_folder);
  ros::NodeHandle n("~");
  readParameters(n);
  for (int i = 0; i < NUM_OF_CAM; i++) tracker_data[i].readIntrinsicParameter(CAM_NAMES[i]);
  if (FISHEYE) {
    for (int i = 0; i < NUM_OF_CAM; i++) {
      tracker_data[i].fisheye_mask = cv::imread(FISHEYE_MASK, 0);
      if (!tracker_data[i].fisheye_mask.data) {
        ROS_ERROR("load mask fail");
        std::exit(1);
      }
    }
  }
}

int tracker_max_cnt() { return MAX_CNT; }
int tracker_freq() { return FREQ; }

bool tracker_process(const cv::Mat &img, double t, std::vector<TrackedPoint> &out) {
  out.clear();
  if (first_image_flag) {
    first_image_flag = false;
    first_image_time = t;
    last_image_time = t;
    return false;
  }
  if (t - last_image_time > 1.0 || t < last_image_time) {
    // Their node resets the tracker and asks the estimator to restart; our folders have no
    // gaps, so this is reported and the run stops rather than silently diverging from theirs.
    ROS_ERROR("image discontinue at %.9f (previous %.9f)", t, last_image_time);
    std::exit(3);
  }
  last_image_time = t;
  // frequency control (as their node)
  if (std::round(1.0 * pub_count / (t - first_image_time)) <= FREQ) {
    PUB_THIS_FRAME = true;
    if (std::abs(1.0 * pub_count / (t - first_image_time) - FREQ) < 0.01 * FREQ) {
      first_image_time = t;
      pub_count = 0;
    }
  } else {
    PUB_THIS_FRAME = false;
  }
  for (int i = 0; i < NUM_OF_CAM; i++) tracker_data[i].readImage(img.rowRange(ROW * i, ROW * (i + 1)), t);
  for (unsigned int i = 0;; i++) {
    bool completed = false;
    for (int j = 0; j < NUM_OF_CAM; j++) completed |= tracker_data[j].updateID(i);
    if (!completed) break;
  }
  if (!PUB_THIS_FRAME) return false;
  pub_count++;
  for (int i = 0; i < NUM_OF_CAM; i++) {
    const FeatureTracker &td = tracker_data[i];
    for (unsigned int j = 0; j < td.ids.size(); j++) {
      if (td.track_cnt[j] > 1) {
        // their node sends id * NUM_OF_CAM + cam as a float channel; NUM_OF_CAM is 1
        out.push_back({td.ids[j] * NUM_OF_CAM + i, td.cur_un_pts[j].x, td.cur_un_pts[j].y, td.cur_pts[j].x,
                       td.cur_pts[j].y, td.pts_velocity[j].x, td.pts_velocity[j].y});
      }
    }
  }
  if (!init_pub) {  // their node does not publish the first frame (no optical-flow speed yet)
    init_pub = true;
    return false;
  }
  return true;
}

}  // namespace vf
