// KLT frontend per stereo frame as vid_run / vid_track run it: the consecutive frames of a
// rendered vid17_like sequence (10 s, rendered once by vid_sim into the build tree), the gyro
// fed to the tracker in time order (gyro prediction), and the parameters of
// config/sim/frontend.yaml. One core (cv::setNumThreads(1)); images are decoded before timing.
//
// VID_BENCH_SEQUENCE=<dataset folder> runs another sequence instead (for example
// demo_out/seq); VID_BENCH_MAX_FRAMES (default 300) caps the frames held in memory;
// VID_BENCH_CONFIG=<frontend yaml> replaces config/sim/frontend.yaml.
//
// Counters: median and p99 of the whole process() call, and the median of each stage
// (pyramids, temporal = KLT + birth-patch refinement + RANSAC, detection, stereo) [ms].
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "frontend/frontend_params_yaml.h"
#include "frontend/klt_tracker.h"
#include "io/dataset_reader.h"

namespace fs = std::filesystem;

namespace vid {
namespace {

/// The sequence in memory: gyro samples and decoded stereo frames in time order.
struct Sequence {
  struct Frame {
    TimeNs t_ns = 0;
    cv::Mat left, right;
    std::size_t imu_end = 0;  ///< IMU samples [0, imu_end) precede this frame
  };
  std::vector<ImuSample> imu;
  std::vector<Frame> frames;
  std::vector<CameraCalib> cams;
  std::string source;
};

fs::path sequence_dir() {
  if (const char* env = std::getenv("VID_BENCH_SEQUENCE")) return env;
  const fs::path dir = fs::path(VID_BINARY_DIR) / "bench" / "frontend" / "vid17_like_10s";
  if (fs::exists(dir / "mav0" / "cam1" / "data.csv")) return dir;
  const fs::path sim = fs::path(VID_BINARY_DIR) / "bin" / "vid_sim";
  const fs::path preset = fs::path(VID_SOURCE_DIR) / "config" / "sim" / "vid17_like.yaml";
  const std::string cmd = sim.string() + " --scenario " + preset.string() + " --out " +
                          dir.string() + " --duration 10 > /dev/null 2>&1";
  if (!fs::exists(sim) || std::system(cmd.c_str()) != 0) {
    fs::remove_all(dir);
    throw std::runtime_error("bench_klt_sequence: cannot render " + dir.string() +
                             " (build vid_sim_app first)");
  }
  return dir;
}

const Sequence& sequence() {
  static const Sequence s = [] {
    Sequence r;
    const fs::path dir = sequence_dir();
    std::size_t max_frames = 300;
    if (const char* env = std::getenv("VID_BENCH_MAX_FRAMES")) max_frames = std::stoul(env);
    io::ReaderOptions ropt;
    ropt.read_features = false;
    ropt.read_groundtruth = false;
    io::DatasetReader reader(dir, ropt);
    const auto& cams = reader.calibration().cameras;
    if (cams.size() < 2) throw std::runtime_error(dir.string() + ": needs cam0 and cam1");
    r.cams = {cams[0], cams[1]};
    while (r.frames.size() < max_frames) {
      auto m = reader.next();
      if (!m) break;
      if (const auto* imu = std::get_if<ImuSample>(&*m)) {
        r.imu.push_back(*imu);
        continue;
      }
      const auto* frame = std::get_if<ImageFrame>(&*m);
      if (!frame) continue;
      Sequence::Frame f;
      f.t_ns = frame->t_ns;
      f.imu_end = r.imu.size();
      for (const auto& ref : frame->images) {
        if (ref.cam_id == r.cams[0].cam_id) f.left = cv::imread(ref.path, cv::IMREAD_GRAYSCALE);
        if (ref.cam_id == r.cams[1].cam_id) f.right = cv::imread(ref.path, cv::IMREAD_GRAYSCALE);
      }
      if (!f.left.empty()) r.frames.push_back(std::move(f));
    }
    r.source = dir.filename().string() + " (" + std::to_string(r.frames.size()) + " frames)";
    return r;
  }();
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

double p99(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, v.size() * 99 / 100)];
}

/// One benchmark iteration = one pass over the sequence with a fresh tracker.
void BM_KltStereoSequence(benchmark::State& state) {
  cv::setNumThreads(1);
  const Sequence& s = sequence();
  const char* config = std::getenv("VID_BENCH_CONFIG");
  const FrontendParams params = load_frontend_params(
      config ? fs::path(config) : fs::path(VID_SOURCE_DIR) / "config" / "sim" / "frontend.yaml");
  std::vector<double> total, pyr, temporal, detect, stereo;
  double features = 0, matched = 0, gyro = 0, tmpl_it = 0, tmpl_n = 0, klt = 0, pyr_frames = 0;
  double direct = 0, previous = 0, detected = 0, stereo_direct = 0;
  for (auto _ : state) {
    KltTracker tracker(params, s.cams);
    std::size_t next_imu = 0;
    double pass_ms = 0;
    for (const auto& f : s.frames) {
      for (; next_imu < f.imu_end; ++next_imu) tracker.add_imu(s.imu[next_imu]);
      const FeatureFrame ff = tracker.process(f.t_ns, f.left, f.right);
      benchmark::DoNotOptimize(ff.observations.data());
      const TrackerStats& st = tracker.stats();
      pass_ms += st.ms_total;
      total.push_back(st.ms_total);
      pyr.push_back(st.ms_pyramid);
      temporal.push_back(st.ms_temporal);
      detect.push_back(st.ms_detect);
      stereo.push_back(st.ms_stereo);
      features += static_cast<double>(tracker.tracks().size());
      matched += st.stereo_matched;
      gyro += st.gyro_used ? 1.0 : 0.0;
      tmpl_it += st.template_iterations;
      tmpl_n += st.klt_tracked + st.template_rejected;
      klt += st.klt_points;
      pyr_frames += st.pyramids > 0 ? 1.0 : 0.0;
      direct += st.direct_aligned;
      previous += st.previous;
      detected += st.detected;
      stereo_direct += st.stereo_direct;
    }
    state.SetIterationTime(pass_ms * 1e-3);
  }
  const double n = static_cast<double>(total.size());
  double sum = 0;
  for (const double v : total) sum += v;
  state.counters["mean_ms"] = sum / static_cast<double>(std::max<std::size_t>(1, total.size()));
  state.counters["median_ms"] = median(total);
  state.counters["p99_ms"] = p99(total);
  state.counters["pyr_ms"] = median(pyr);
  state.counters["temporal_ms"] = median(temporal);
  state.counters["detect_ms"] = median(detect);
  state.counters["stereo_ms"] = median(stereo);
  state.counters["features"] = features / n;
  state.counters["stereo"] = matched / n;
  state.counters["gyro_frac"] = gyro / n;
  // Gauss-Newton iterations per temporal birth-patch alignment.
  state.counters["tmpl_iters"] = tmpl_n > 0 ? tmpl_it / tmpl_n : 0.0;
  // Points through pyramidal KLT per frame, share of frames that built a pyramid, share of the
  // temporal tracks aligned directly (direct_alignment).
  state.counters["klt_pts"] = klt / n;
  state.counters["pyr_frames"] = pyr_frames / n;
  state.counters["direct"] = previous > 0 ? direct / previous : 0.0;
  // New features per frame, and stereo matches per frame made by the birth-patch alignment alone.
  state.counters["new"] = detected / n;
  state.counters["stereo_direct"] = stereo_direct / n;
  state.SetLabel(s.source);
}
BENCHMARK(BM_KltStereoSequence)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(2);

}  // namespace
}  // namespace vid
