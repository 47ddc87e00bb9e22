// KLT frontend per-frame cost on 640x480 rendered frames, 150 features, one core.
// Frames: a vid17_like rendering (rendered once here by vid_sim into the build tree, or the
// one the scoring test left there); without vid_sim, synthetic warped textures.
// Reports median and p99 per frame as counters (ms); frames are played forward then backward
// so that tracking never jumps.
// Not what vid_run does (no gyro, default parameters, almost no detection, 60 frames): about
// 8 % lighter than the real sequence. bench_klt_sequence.cpp (bench_frontend_sequence)
// measures the frontend as vid_run/vid_track run it.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdlib>
#include <filesystem>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "frontend/klt_tracker.h"
#include "io/csv_reader.h"
#include "synthetic_images.h"

namespace fs = std::filesystem;

namespace vid {
namespace {

struct Frames {
  std::vector<cv::Mat> left, right;
  std::vector<CameraCalib> cams;
  std::string source;
};

CameraCalib d435(int id, double y) {
  CameraCalib c;
  c.cam_id = id;
  c.intrinsics << 382.59014892578125, 382.59014892578125, 323.421142578125, 242.06617736816406;
  c.T_IC.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  c.T_IC.translation() << 0.18875, y, 0.0555;
  return c;
}

std::vector<std::string> list_pngs(const fs::path& csv) {
  std::vector<std::string> out;
  io::CsvReader in(csv);
  while (in.next_row()) {
    in.expect_columns(2);
    out.push_back((csv.parent_path() / "data" / std::string(in.field(1))).string());
  }
  return out;
}

const Frames& frames() {
  static const Frames f = [] {
    Frames r;
    r.cams = {d435(0, 0.00175), d435(1, -0.04825)};
    const fs::path sim = fs::path(VID_BINARY_DIR) / "bin" / "vid_sim";
    const fs::path dir = fs::path(VID_BINARY_DIR) / "bench" / "frontend" / "vid17_like_4s";
    const fs::path preset = fs::path(VID_SOURCE_DIR) / "config" / "sim" / "vid17_like_short.yaml";
    if (!fs::exists(dir / "mav0" / "cam1" / "data.csv") && fs::exists(sim) && fs::exists(preset)) {
      const std::string cmd = sim.string() + " --scenario " + preset.string() + " --out " +
                              dir.string() + " --duration 4 > /dev/null 2>&1";
      if (std::system(cmd.c_str()) != 0) fs::remove_all(dir);
    }
    if (fs::exists(dir / "mav0" / "cam1" / "data.csv")) {
      const auto l = list_pngs(dir / "mav0" / "cam0" / "data.csv");
      const auto rr = list_pngs(dir / "mav0" / "cam1" / "data.csv");
      // Skip the take-off second; keep 60 frames in memory.
      for (std::size_t i = 30; i < std::min<std::size_t>(l.size(), 90); ++i) {
        r.left.push_back(cv::imread(l[i], cv::IMREAD_GRAYSCALE));
        r.right.push_back(cv::imread(rr[i], cv::IMREAD_GRAYSCALE));
      }
      r.source = "vid17_like rendered";
    }
    if (r.left.empty()) {
      const cv::Mat base = test::textured_image(640, 480, 1);
      for (int k = 0; k < 60; ++k) {
        r.left.push_back(test::warp(base, cv::Matx33d(1, 0, 1.5 * k, 0, 1, 0.5 * k, 0, 0, 1)));
        r.right.push_back(test::warp(base, cv::Matx33d(1, 0, 1.5 * k - 15, 0, 1, 0.5 * k, 0, 0, 1)));
      }
      r.source = "synthetic warps";
    }
    return r;
  }();
  return f;
}

/// CPU time of this thread [ms]: unlike wall time, not inflated by other processes on a
/// shared machine.
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

void run(benchmark::State& state, bool stereo) {
  cv::setNumThreads(1);
  const Frames& f = frames();
  FrontendParams p;
  p.num_features = 150;
  std::vector<CameraCalib> cams = f.cams;
  if (!stereo) cams.resize(1);
  KltTracker tracker(p, cams);
  std::vector<double> ms, cpu;
  const std::size_t n = f.left.size();
  std::size_t k = 0;
  TimeNs t = 0;
  double features = 0, matched = 0;
  double pyr = 0, temporal = 0, detect = 0, stereo_ms = 0;
  for (auto _ : state) {
    // Ping-pong through the frames: 0..n-1, n-2..1, 0..
    const std::size_t period = 2 * n - 2;
    const std::size_t ph = k % period;
    const std::size_t i = ph < n ? ph : period - ph;
    ++k;
    const double c0 = thread_cpu_ms();
    const auto t0 = std::chrono::steady_clock::now();
    const FeatureFrame ff = stereo ? tracker.process(t, f.left[i], f.right[i])
                                   : tracker.process(t, f.left[i]);
    const auto t1 = std::chrono::steady_clock::now();
    cpu.push_back(thread_cpu_ms() - c0);
    benchmark::DoNotOptimize(ff.observations.data());
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    features += static_cast<double>(tracker.tracks().size());
    matched += tracker.stats().stereo_matched;
    pyr += tracker.stats().ms_pyramid;
    temporal += tracker.stats().ms_temporal;
    detect += tracker.stats().ms_detect;
    stereo_ms += tracker.stats().ms_stereo;
    t += 33'333'333;
  }
  std::sort(ms.begin(), ms.end());
  std::sort(cpu.begin(), cpu.end());
  const std::size_t i99 = std::min(ms.size() - 1, ms.size() * 99 / 100);
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["p99_ms"] = ms[i99];
  state.counters["cpu_median_ms"] = cpu[cpu.size() / 2];
  state.counters["cpu_p99_ms"] = cpu[i99];
  const double n_it = static_cast<double>(ms.size());
  state.counters["features"] = features / n_it;
  // Mean stage times [ms]: pre-processing + pyramids, temporal (KLT, template, RANSAC),
  // detection, stereo.
  state.counters["pyr_ms"] = pyr / n_it;
  state.counters["temporal_ms"] = temporal / n_it;
  state.counters["detect_ms"] = detect / n_it;
  if (stereo) state.counters["stereo_ms"] = stereo_ms / n_it;
  if (stereo) state.counters["stereo"] = matched / static_cast<double>(ms.size());
  state.SetLabel(f.source);
}

void BM_KltStereo640x480(benchmark::State& state) { run(state, true); }
void BM_KltMono640x480(benchmark::State& state) { run(state, false); }
BENCHMARK(BM_KltStereo640x480)->Unit(benchmark::kMillisecond)->Iterations(600);
BENCHMARK(BM_KltMono640x480)->Unit(benchmark::kMillisecond)->Iterations(600);

}  // namespace
}  // namespace vid
