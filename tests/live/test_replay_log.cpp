// vid_replay's event log read back with LCM's own C++ API (lcm::LogFile), on the EuRoC sample.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include "io/lcm/lcm_convert.h"
#include "replay/replay.h"

namespace vid::replay {
namespace {

namespace fs = std::filesystem;

TEST(ReplayLog, ReadsBackWithLcmLogFile) {
  const fs::path sample = fs::path(VID_TEST_DATA_DIR) / "euroc_sample";
  const fs::path log = fs::temp_directory_path() / ("vid_replay_test_" + std::to_string(::getpid()) + ".log");
  ReplayOptions o;
  o.dataset = sample;
  o.lcm_url = "memq://";
  o.fast = true;
  o.log = log;
  o.progress = false;
  std::atomic<bool> stop{false};
  const nlohmann::json report = replay(o, stop);

  lcm::LogFile f(log.string(), "r");
  ASSERT_TRUE(f.good());
  std::map<std::string, long> counts;
  std::vector<ImuSample> imu;
  std::vector<image_t> images;
  std::int64_t last_us = INT64_MIN;
  while (const lcm::LogEvent* ev = f.readNextEvent()) {
    ++counts[ev->channel];
    EXPECT_GE(ev->timestamp, last_us);
    last_us = ev->timestamp;
    if (ev->channel == "IMU") {
      imu.push_back(lcm_io::from_lcm(lcm_io::decode<imu_t>(ev->data, static_cast<std::size_t>(ev->datalen), "IMU"), "IMU"));
      EXPECT_EQ(ev->timestamp, imu.back().t_ns / 1000);  // event time = data time [us]
    } else if (ev->channel == "CAM0") {
      images.push_back(lcm_io::decode<image_t>(ev->data, static_cast<std::size_t>(ev->datalen), "CAM0"));
    }
  }
  ASSERT_EQ(counts.size(), report["published"].size());
  for (const auto& [channel, n] : counts) EXPECT_EQ(n, report["published"][channel].get<long>()) << channel;

  // The first IMU row and the first image, exactly as in the folder.
  std::ifstream csv(sample / "mav0" / "imu0" / "data.csv");
  std::string line;
  while (std::getline(csv, line) && (line.empty() || line[0] == '#')) {
  }
  ASSERT_FALSE(imu.empty());
  EXPECT_EQ(imu.front().t_ns, std::stoll(line.substr(0, line.find(','))));
  ASSERT_EQ(images.size(), 2u);
  const cv::Mat png = cv::imread((sample / "mav0" / "cam0" / "data" / (std::to_string(images[0].timestamp) + ".png")).string(),
                                 cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(png.empty());
  EXPECT_NO_THROW(lcm_io::validate_image(images[0], "CAM0", 1));
  ASSERT_EQ(images[0].width, png.cols);
  ASSERT_EQ(images[0].height, png.rows);
  ASSERT_TRUE(png.isContinuous());
  EXPECT_TRUE(std::equal(images[0].data.begin(), images[0].data.end(), png.data));
  fs::remove(log);
}

TEST(ReplayLog, MissingDatasetIsAnErrorNamingIt) {
  ReplayOptions o;
  o.dataset = "/nonexistent/vid_replay_dataset";
  o.lcm_url = "memq://";
  o.fast = true;
  std::atomic<bool> stop{false};
  try {
    replay(o, stop);
    FAIL() << "no exception";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("vid_replay_dataset"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vid::replay
