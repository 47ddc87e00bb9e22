/// Decode-ahead reader (system/ vid_dataset_input: system::Prefetcher, used by vid_run and vid_replay): whatever
/// the number of decoding threads and however small the queue, the consumer gets the same
/// measurements in the same order with the same decoded images as with inline decoding; the
/// time window, unreadable images, reader errors and early destruction behave as inline.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "io/dataset_reader.h"
#include "io/dataset_writer.h"
#include "io/errors.h"
#include "vid_system/prefetch.h"

namespace vid::system {
namespace {

namespace fs = std::filesystem;

constexpr TimeNs kT0 = 1'000'000'000'000LL;
constexpr int kFrames = 24;       // stereo frames at 20 Hz
constexpr int kBadFrame = 7;      // its right image is not a PNG
constexpr TimeNs kImuDt = 5'000'000;  // 200 Hz

/// A small stereo dataset with random-texture images (seeded) and one corrupt image file.
fs::path make_dataset(const std::string& name) {
  const fs::path root = fs::temp_directory_path() / ("vid_prefetch_" + name);
  fs::remove_all(root);
  {
    io::DatasetWriter w(root);
    for (int cam = 0; cam < 2; ++cam) {
      CameraCalib c;
      c.cam_id = cam;
      c.width = 64;
      c.height = 48;
      w.write_camera_calibration(c);
    }
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> pixel(0, 255);
    for (TimeNs t = kT0; t <= kT0 + (kFrames - 1) * 50'000'000LL; t += kImuDt) {
      w.write(ImuSample{t, Eigen::Vector3d(0.01, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 9.81)});
      if ((t - kT0) % 50'000'000LL != 0) continue;
      for (int cam = 0; cam < 2; ++cam) {
        cv::Mat g(48, 64, CV_8UC1);
        for (int r = 0; r < g.rows; ++r)
          for (int c = 0; c < g.cols; ++c) g.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(pixel(rng));
        w.write_image(cam, t, g);
      }
    }
  }
  const TimeNs t_bad = kT0 + kBadFrame * 50'000'000LL;
  std::ofstream(root / "mav0" / "cam1" / "data" / (std::to_string(t_bad) + ".png"), std::ios::trunc) << "not a png";
  return root;
}

std::vector<Prefetched> read_all(const fs::path& root, const PrefetchOptions& po) {
  io::DatasetReader reader(root);
  Prefetcher p(reader, po);
  p.wait_ready();
  std::vector<Prefetched> out;
  while (auto m = p.next()) out.push_back(std::move(*m));
  EXPECT_EQ(p.stats().frames_decoded, kFrames);
  return out;
}

bool same_image(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  return a.size() == b.size() && a.type() == b.type() && cv::countNonZero(a != b) == 0;
}

void expect_same(const std::vector<Prefetched>& a, const std::vector<Prefetched>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].m.index(), b[i].m.index()) << i;
    ASSERT_EQ(stamp_of(a[i].m), stamp_of(b[i].m)) << i;
    EXPECT_EQ(a[i].t0, b[i].t0);
    ASSERT_EQ(a[i].images.size(), b[i].images.size()) << i;
    for (std::size_t k = 0; k < a[i].images.size(); ++k) {
      EXPECT_EQ(a[i].images[k].first, b[i].images[k].first);
      EXPECT_TRUE(same_image(a[i].images[k].second, b[i].images[k].second)) << i << " cam " << k;
    }
  }
}

TEST(Prefetcher, ThreadedEqualsInline) {
  const fs::path root = make_dataset("equal");
  PrefetchOptions inline_opt;
  inline_opt.decode_threads = 0;
  const auto ref = read_all(root, inline_opt);

  long frames = 0;
  for (const auto& p : ref) {
    if (!std::holds_alternative<ImageFrame>(p.m)) {
      EXPECT_TRUE(p.images.empty());
      continue;
    }
    ASSERT_EQ(p.images.size(), 2u);
    EXPECT_EQ(p.images[0].first, 0);
    EXPECT_EQ(p.images[1].first, 1);
    EXPECT_FALSE(p.images[0].second.empty());
    EXPECT_EQ(p.images[1].second.empty(), frames == kBadFrame);  // unreadable -> empty Mat
    ++frames;
  }
  EXPECT_EQ(frames, kFrames);

  for (int threads : {1, 2, 3}) {
    for (std::size_t max_frames : {std::size_t{0}, std::size_t{1}, std::size_t{4}}) {
      SCOPED_TRACE("threads " + std::to_string(threads) + ", max_frames " + std::to_string(max_frames));
      PrefetchOptions po;
      po.decode_threads = threads;
      po.max_frames = max_frames;
      po.capacity = max_frames == 1 ? 3 : 256;  // also a queue shorter than the IMU rows between frames
      expect_same(read_all(root, po), ref);
    }
  }
}

TEST(Prefetcher, WindowIsRelativeToTheFirstMeasurement) {
  const fs::path root = make_dataset("window");
  for (int threads : {0, 2}) {
    PrefetchOptions po;
    po.decode_threads = threads;
    po.start_s = 0.2;
    po.end_s = 0.6;
    io::DatasetReader reader(root);
    Prefetcher p(reader, po);
    std::vector<TimeNs> t;
    while (auto m = p.next()) {
      EXPECT_EQ(m->t0, kT0);
      t.push_back(stamp_of(m->m));
    }
    ASSERT_FALSE(t.empty());
    EXPECT_EQ(t.front(), kT0 + 200'000'000);
    EXPECT_EQ(t.back(), kT0 + 600'000'000);
  }
}

TEST(Prefetcher, ReaderErrorComesAfterTheRowsBeforeIt) {
  const fs::path root = make_dataset("error");
  std::ofstream(root / "mav0" / "imu0" / "data.csv", std::ios::app) << "garbage,row\n";
  std::vector<std::size_t> counts;
  for (int threads : {0, 1, 2}) {
    io::DatasetReader reader(root);
    PrefetchOptions po;
    po.decode_threads = threads;
    po.max_frames = 2;
    Prefetcher p(reader, po);
    std::size_t n = 0;
    EXPECT_THROW(
        {
          while (p.next()) ++n;
        },
        io::DatasetError)
        << "threads " << threads;
    counts.push_back(n);
  }
  EXPECT_GT(counts[0], 0u);
  EXPECT_EQ(counts[1], counts[0]);
  EXPECT_EQ(counts[2], counts[0]);
}

TEST(Prefetcher, DestroyedMidStreamStopsItsThreads) {
  const fs::path root = make_dataset("early");
  io::DatasetReader reader(root);
  PrefetchOptions po;
  po.decode_threads = 2;
  po.max_frames = 2;
  po.capacity = 8;
  {
    Prefetcher p(reader, po);
    long taken_frames = 0;
    for (int i = 0; i < 20; ++i) {
      auto m = p.next();
      ASSERT_TRUE(m.has_value());
      taken_frames += std::holds_alternative<ImageFrame>(m->m) ? 1 : 0;
    }
    EXPECT_GT(taken_frames, 0);
    // Decoders only take frames from the queue, which holds at most max_frames of them.
    EXPECT_LE(p.stats().frames_decoded, taken_frames + 2);
  }  // the destructor must return (the threads are blocked on a full queue)
  SUCCEED();
}

}  // namespace
}  // namespace vid::system
