// Per-message costs on vid_live's LCM thread: decoding (IMU, a 640x480 mono image) and the
// reorder window (insert + release at IMU rate with 30 Hz stereo images interleaved).
#include <benchmark/benchmark.h>

#include "io/lcm/lcm_convert.h"
#include "live/reorder_window.h"

namespace vid::live {
namespace {

void BM_DecodeImu(benchmark::State& state) {
  ImuSample s{123, Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.0, 0.0, 9.81)};
  const auto bytes = lcm_io::encode(lcm_io::to_lcm(s));
  for (auto _ : state) {
    ImuSample r = lcm_io::from_lcm(lcm_io::decode<imu_t>(bytes.data(), bytes.size(), "IMU"), "IMU");
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_DecodeImu);

void BM_DecodeImage640x480(benchmark::State& state) {
  std::vector<std::uint8_t> px(640 * 480);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<std::uint8_t>(i * 31);
  const auto bytes = lcm_io::encode(lcm_io::make_image(1, 0, 640, 480, px.data(), 640));
  for (auto _ : state) {
    const image_t m = lcm_io::decode<image_t>(bytes.data(), bytes.size(), "CAM0");
    lcm_io::validate_image(m, "CAM0", 2);
    cv::Mat img(m.height, m.width, CV_8UC1);
    std::copy(m.data.begin(), m.data.end(), img.data);
    benchmark::DoNotOptimize(img.data);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes.size()));
}
BENCHMARK(BM_DecodeImage640x480);

void BM_ReorderWindowOneSecond(benchmark::State& state) {
  // 1 s of data: 400 IMU, 100 rotor, 2 x 31 images (every 32.5 ms on the IMU grid, no pixels),
  // released with a 30 ms window.
  std::vector<LiveItem> items;
  for (TimeNs t = 0; t < 1'000'000'000; t += 2'500'000) {
    LiveItem it;
    it.stream = Stream::kImu;
    it.t_ns = t;
    ImuSample s;
    s.t_ns = t;
    it.data = s;
    items.push_back(it);
    if (t % 10'000'000 == 0) items.push_back(LiveItem{Stream::kRotor, t, {}, RotorSample{t, {1, 2, 3, 4}}});
    if (t % 32'500'000 == 0)
      for (int c = 0; c < 2; ++c)
        items.push_back(LiveItem{c == 0 ? Stream::kCam0 : Stream::kCam1, t, {}, CameraImage{t, c, {}}});
  }
  for (auto _ : state) {
    ReorderWindow w(30'000'000);
    std::size_t out = 0;
    for (const auto& it : items) {
      w.insert(it);
      out += w.pop_ready().size();
    }
    out += w.flush().size();
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * items.size()));
}
BENCHMARK(BM_ReorderWindowOneSecond);

}  // namespace
}  // namespace vid::live
