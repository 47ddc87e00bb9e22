#include "track_session.h"

#include <cstdio>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <variant>

#include "frontend/image_decode.h"
#include "frontend/klt_tracker.h"
#include "frontend/track_drawing.h"
#include "io/dataset_reader.h"
#include "vid_system/frame_faults.h"
#include "vid_system/frontend_stage.h"
#include "vid_system/image_depth.h"
#include "vid_system/outputs.h"
#include "vid_system/progress.h"

namespace vid::app {
namespace {

struct CsvFile {
  std::FILE* f = nullptr;
  explicit CsvFile(const std::filesystem::path& p) : f(std::fopen(p.c_str(), "w")) {
    if (!f) throw std::runtime_error(p.string() + ": cannot open for writing");
  }
  ~CsvFile() {
    if (f) std::fclose(f);
  }
};

}  // namespace

TrackSummary run_tracking(const TrackOptions& o) {
  io::ReaderOptions ropt;
  ropt.read_features = false;
  ropt.read_groundtruth = false;
  ropt.list_missing_images = true;  // a missing image skips its frame (FrameFaults), as an unreadable one does
  io::DatasetReader reader(o.dataset, ropt);
  const auto& cams = reader.calibration().cameras;
  if (cams.empty()) throw io::DatasetError(reader.mav0().string() + ": no camN/sensor.yaml found");
  if (!reader.has_stream("cam0")) {
    throw io::DatasetError(reader.mav0().string() + ": no cam0/data.csv (vid_track needs images)");
  }
  // The frontend as vid_run / vid_live run it (cam 1 only for a stereo frontend with cam 1 images).
  system::FrontendStage frontend(o.params, cams, reader.has_stream("cam1"));
  const bool stereo = frontend.cameras() == 2;
  const KltTracker& tracker = frontend.tracker();
  // 16-bit images: one scale per camera for the whole run, from samples of the stream.
  const system::CameraDepths depths = system::camera_bit_depths(reader.mav0(), o.params.image_bit_depth);
  TrackDrawer drawer;
  if (o.draw_dir) std::filesystem::create_directories(*o.draw_dir);

  CsvFile csv(o.out_csv);
  std::fprintf(csv.f, "%s\n", system::tracks_csv_header().c_str());
  system::ProgressBar bar("vid_track", 1.0);
  TrackSummary s;
  system::FrameFaults faults;
  faults.set_strict(o.strict);
  double sum_ms = 0, sum_feat = 0, sum_stereo = 0;
  while (auto m = reader.next()) {
    if (const auto* imu = std::get_if<ImuSample>(&*m)) {
      frontend.add_imu(*imu);
      continue;
    }
    const auto* frame = std::get_if<ImageFrame>(&*m);
    if (!frame) continue;
    cv::Mat left, right;
    bool usable = true;
    for (const auto& ref : frame->images) {
      const int k = ref.cam_id == cams[0].cam_id ? 0 : stereo && ref.cam_id == cams[1].cam_id ? 1 : -1;
      if (k < 0) continue;
      cv::Mat g = decode_gray8(ref.path, nullptr, depths.bits(ref.cam_id));
      if (!system::check_frame_image(g, ref.path, cams[k].width, cams[k].height, faults)) usable = false;
      (k == 0 ? left : right) = g;
    }
    if (!usable) continue;       // skipped: warned and counted (or thrown under strict)
    if (left.empty()) continue;  // a right-only timestamp: nothing to track
    const FeatureFrame ff = frontend.track(frame->t_ns, left, right);
    for (const auto& ob : ff.observations) std::fprintf(csv.f, "%s\n", system::tracks_csv_row(ff.t_ns, ob).c_str());
    const TrackerStats& st = tracker.stats();
    if (o.draw_dir) {
      drawer.update(tracker.tracks());
      if (s.frames % o.draw_every == 0) {
        char caption[160];
        std::snprintf(caption, sizeof caption, "t=%lld  tracks %zu  new %d  stereo %d  kept %d/%d",
                      static_cast<long long>(ff.t_ns), tracker.tracks().size(), st.detected,
                      st.stereo_matched, st.ransac_inliers, st.previous);
        const auto path = *o.draw_dir / (std::to_string(ff.t_ns) + ".png");
        if (!cv::imwrite(path.string(), drawer.draw(left, right, tracker.tracks(), caption))) {
          throw std::runtime_error(path.string() + ": cannot write image");
        }
      }
    }
    ++s.frames;
    s.observations += ff.observations.size();
    sum_ms += st.ms_total;
    sum_feat += static_cast<double>(tracker.tracks().size());
    sum_stereo += st.stereo_matched;
    char extra[64];
    std::snprintf(extra, sizeof extra, "%zu frames, %zu tracks", s.frames, tracker.tracks().size());
    bar.update(reader.progress(), extra);
  }
  bar.finish();
  faults.report_rest();
  s.frames_skipped = static_cast<std::size_t>(faults.total());
  if (s.frames > 0) {
    s.mean_ms = sum_ms / static_cast<double>(s.frames);
    s.mean_features = sum_feat / static_cast<double>(s.frames);
    s.mean_stereo = sum_stereo / static_cast<double>(s.frames);
  }
  return s;
}

}  // namespace vid::app
