#include "replay/replay.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <fstream>
#include <algorithm>
#include <queue>
#include <random>
#include <set>
#include <thread>

#include <lcm/lcm-cpp.hpp>

#include "io/csv_reader.h"
#include "io/dataset_reader.h"
#include "io/lcm/lcm_convert.h"
#include "vid_system/data_window.h"
#include "vid_system/image_depth.h"
#include "vid_system/prefetch.h"
#include "vid_system/progress.h"

namespace vid::replay {

namespace fs = std::filesystem;

namespace {

/// One message on its way out. `send` orders publication (= t unless delayed by a fault).
struct Outgoing {
  TimeNs t = 0, send = 0;
  std::uint64_t seq = 0;
  std::string channel, stream;
  std::vector<std::uint8_t> bytes;
  bool regular = true;  ///< false for injected copies and malformed payloads
};
struct Later {
  bool operator()(const Outgoing& a, const Outgoing& b) const {
    return a.send != b.send ? a.send > b.send : a.seq > b.seq;
  }
};

/// Rows of a CSV that are not comments or blank (image count per camera).
std::size_t data_rows(const fs::path& csv) {
  io::CsvReader in(csv);
  while (in.next_row()) {
  }
  return in.rows();
}

/// The camera travels over LCM as images (image_t) only: a folder without cam0/ (feature-level
/// feat0/ data, or no camera) would replay IMU and rotors alone, which a receiver cannot tell
/// from a camera that never sends. Refused in one line unless --no-camera says so.
void check_camera(const io::DatasetReader& reader, const ReplayOptions& opt) {
  const std::string dir = opt.dataset.string();
  const bool images = reader.has_stream("cam0"), features = reader.has_stream("feat0");
  if (opt.no_camera) {
    std::string left_out = images ? (reader.has_stream("cam1") ? "cam0/, cam1/" : "cam0/") : "";
    if (features) left_out += std::string(left_out.empty() ? "" : "; ") + "feat0/: feature-level, no LCM message";
    spdlog::warn("{}: --no-camera: publishing IMU and rotor/thrust messages without the camera{}", dir,
                 left_out.empty() ? "" : " (not published: " + left_out + ")");
    return;
  }
  if (images) return;
  if (features)
    throw std::runtime_error(dir + ": the camera data is feature-level (feat0/, no images), which has no LCM message: "
                                   "run the folder with vid_run --dataset, or pass --no-camera to publish IMU and "
                                   "rotors without the camera");
  throw std::runtime_error(dir + ": no camera images (cam0/) to publish; pass --no-camera to publish IMU and rotors "
                                 "without the camera");
}

}  // namespace

nlohmann::json replay(const ReplayOptions& opt, const std::atomic<bool>& stop) {
  const FaultOptions& fo = opt.faults;
  const lcm_io::ChannelNames& ch = opt.channels;
  io::ReaderOptions ro;
  ro.read_features = false;
  ro.read_groundtruth = false;
  ro.skip_missing_images = true;
  ro.gaps_as_warnings = true;  // published as recorded: the receiver meets the gap and reports it
  ro.warn = [](const std::string& w) { spdlog::warn("{}", w); };
  ro.read_images = !opt.no_camera;
  system::check_dataset_window(opt.dataset, ro, opt.start_s, opt.end_s);
  io::DatasetReader reader(opt.dataset, ro);
  check_camera(reader, opt);
  const std::string rotor_unit = reader.calibration().rotor ? reader.calibration().rotor->unit : "rpm";

  std::unique_ptr<lcm::LCM> lcm;
  if (!opt.lcm_url.empty()) {
    lcm = std::make_unique<lcm::LCM>(opt.lcm_url);
    if (!lcm->good()) throw std::runtime_error(opt.lcm_url + ": LCM cannot open this URL");
  }
  std::unique_ptr<lcm::LogFile> log;
  if (opt.log) {
    if (opt.log->has_parent_path()) fs::create_directories(opt.log->parent_path());
    log = std::make_unique<lcm::LogFile>(opt.log->string(), "w");
    if (!log->good()) throw std::runtime_error(opt.log->string() + ": cannot write the LCM log");
  }

  // Fault plan: images are never dropped among the first 10 or as the last of a camera (a
  // receiver sees a drop as a gap between two images); malformed messages follow IMU messages
  // spread over 10%..90% of the replayed IMU stream.
  std::mt19937_64 rng(fo.seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::map<int, std::size_t> image_count, image_index;
  std::map<std::string, long> stall_images;
  long camera_stalls = 0;  // passes in which the stall withheld images
  TimeNs stall_from = INT64_MAX, stall_to = INT64_MIN;
  for (int cam = 0; cam < 2; ++cam)
    if (reader.has_stream("cam" + std::to_string(cam)))
      image_count[cam] = data_rows(reader.mav0() / ("cam" + std::to_string(cam)) / "data.csv");
  std::set<TimeNs> malformed_at;  // IMU times (unshifted) after which a malformed message goes out
  std::vector<TimeNs> t_imu;       // IMU times of the window
  TimeNs imu_last = INT64_MIN;     // last replayed IMU time (progress)
  TimeNs period = 0;               // shift between two passes (loops > 1)
  auto read_imu_times = [&](TimeNs from, TimeNs to) {
    io::CsvReader in(reader.mav0() / "imu0" / "data.csv");
    while (in.next_row()) {
      const TimeNs t = in.get_int(0, "timestamp [ns]");
      if (t >= from && t <= to) t_imu.push_back(t);
    }
    if (t_imu.empty()) return;
    imu_last = t_imu.back();
    period = t_imu.back() - t_imu.front();
  };
  auto plan_malformed = [&]() {  // once per pass
    malformed_at.clear();
    if (fo.malformed <= 0 || t_imu.empty()) return;
    std::uniform_int_distribution<std::size_t> pick(t_imu.size() / 10, std::max(t_imu.size() / 10, t_imu.size() * 9 / 10));
    while (static_cast<int>(malformed_at.size()) < fo.malformed && malformed_at.size() < t_imu.size())
      malformed_at.insert(t_imu[pick(rng)]);
  };
  const int loops = std::max(1, opt.loops);

  nlohmann::json report;
  std::map<std::string, long> published, reordered, malformed;
  std::map<std::string, long> dropped;
  long duplicated = 0, unreadable = 0, malformed_made = 0;
  std::priority_queue<Outgoing, std::vector<Outgoing>, Later> heap;
  std::uint64_t seq = 0;
  TimeNs max_regular_sent = INT64_MIN;
  std::optional<TimeNs> t0, wall_t0;
  TimeNs t_start = 0, t_end = INT64_MAX;
  TimeNs t_first = 0;  // first replayed measurement: a pass covers [t_first, t_first + period)
  const auto wall_start = std::chrono::steady_clock::now();
  auto wall_anchor = wall_start;
  std::unique_ptr<system::ProgressBar> bar;

  std::map<std::string, long> late;
  const TimeNs late_ns = static_cast<TimeNs>(fo.late_ms * 1e6);
  auto delay = [&]() -> TimeNs {
    if (fo.reorder <= 0.0 || U(rng) >= fo.reorder) return 0;
    return std::max<TimeNs>(1, static_cast<TimeNs>((1.0 - U(rng)) * fo.reorder_max_ms * 1e6));
  };
  // A late message is published late_ms after its time: the receiver has processed past it.
  auto is_late = [&]() { return fo.late > 0.0 && U(rng) < fo.late; };
  auto enqueue = [&](TimeNs t, const std::string& channel, const std::string& stream, std::vector<std::uint8_t> bytes,
                     bool regular, TimeNs send_delay) {
    if (regular && send_delay == 0 && is_late()) {
      ++late[stream];
      regular = false;  // not a reordered arrival: the receiver drops it as late
      send_delay = late_ns;
    }
    heap.push(Outgoing{t, t + send_delay, seq++, channel, stream, std::move(bytes), regular});
  };
  double max_lag_ms = 0.0;  // rate mode: how far publication fell behind the schedule
  auto send = [&](const Outgoing& o) {
    if (!opt.fast) {
      if (!wall_t0) {  // the schedule starts with the first publication
        wall_t0 = o.send;
        wall_anchor = std::chrono::steady_clock::now();
      }
      const auto due = wall_anchor + std::chrono::nanoseconds(static_cast<TimeNs>(
                                        static_cast<double>(o.send - *wall_t0) / std::max(opt.rate, 1e-6)));
      std::this_thread::sleep_until(due);
      max_lag_ms = std::max(max_lag_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - due).count());
    }
    if (lcm && lcm->publish(o.channel, o.bytes.data(), static_cast<unsigned int>(o.bytes.size())) != 0)
      throw std::runtime_error(opt.lcm_url + ": publishing on " + o.channel + " failed");
    if (log) {
      lcm::LogEvent ev;
      ev.timestamp = o.send / 1000;  // data time [us]: lcm-logplayer replays at the recorded rate
      ev.channel = o.channel;
      ev.datalen = static_cast<int32_t>(o.bytes.size());
      ev.data = const_cast<std::uint8_t*>(o.bytes.data());
      if (log->writeEvent(&ev) != 0) throw std::runtime_error(opt.log->string() + ": writing the LCM log failed");
    }
    ++published[o.channel];
    if (o.regular) {
      if (o.t < max_regular_sent) ++reordered[o.stream];  // arrives after a later message
      max_regular_sent = std::max(max_regular_sent, o.t);
    }
  };
  auto send_until = [&](TimeNs t) {
    while (!heap.empty() && heap.top().send <= t) {
      send(heap.top());
      heap.pop();
    }
  };
  auto add_malformed = [&](TimeNs t) {
    const int kind = static_cast<int>(malformed_made++ % 4);
    if (kind == 0) {  // random bytes on the IMU channel
      std::vector<std::uint8_t> junk(40);
      for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
      enqueue(t, ch.imu, "imu", std::move(junk), false, 0);
      ++malformed[ch.imu];
    } else if (kind == 1 || kind == 3) {  // truncated image_t / image_t whose size disagrees
      std::vector<std::uint8_t> px(16, 128);
      image_t m = lcm_io::make_image(t, 0, 4, 4, px.data(), 4);
      if (kind == 3) m.width = 5;
      auto bytes = lcm_io::encode(m);
      if (kind == 1) bytes.resize(bytes.size() / 2);
      enqueue(t, ch.cam0, "cam0", std::move(bytes), false, 0);
      ++malformed[ch.cam0];
    } else {  // an imu_t on the rotor channel (wrong type) or, without rotors, on the thrust channel
      const std::string& c = reader.has_stream("rotor0") ? ch.rotors : ch.thrust;
      enqueue(t, c, "rotors", lcm_io::encode(lcm_io::to_lcm(ImuSample{t, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()})), false, 0);
      ++malformed[c];
    }
  };

  system::PrefetchOptions po;  // one thread reads and decodes ahead of the publishing schedule
  po.start_s = opt.start_s;
  po.end_s = opt.end_s.value_or(-1.0);
  po.decode_threads = 1;
  po.capacity = 256;
  const system::CameraDepths depths = system::camera_bit_depths(reader.mav0(), opt.image_bit_depth);
  po.image_bits = {depths.bits(0), depths.bits(1)};
  for (int pass = 0; pass < loops && !stop.load(); ++pass) {
    std::optional<io::DatasetReader> again;  // a pass reads the folder afresh
    if (pass > 0) again.emplace(opt.dataset, ro);
    system::Prefetcher prefetch(pass > 0 ? *again : reader, po);
    if (!opt.fast) prefetch.wait_ready();
    image_index.clear();
    if (pass > 0) plan_malformed();
    bool stalled = false;
    const TimeNs shift = pass * period;
    while (auto p = prefetch.next()) {
      if (stop.load()) break;
      const Measurement* m = &p->m;
      const TimeNs t_data = stamp_of(*m);  // as recorded: fault plans and stalls refer to it
      if (!t0) {
        t0 = p->t0;
        t_start = *t0 + static_cast<TimeNs>(opt.start_s * 1e9);
        if (opt.end_s) t_end = *t0 + static_cast<TimeNs>(*opt.end_s * 1e9);
        if (opt.progress) bar = std::make_unique<system::ProgressBar>("vid_replay", 1.0);
        t_first = t_data;
        if (fo.malformed > 0 || opt.progress || loops > 1) read_imu_times(t_start, t_end);
        if (loops > 1 && period <= 0) throw std::runtime_error(opt.dataset.string() + ": --loop needs at least two IMU samples");
        plan_malformed();
        if (fo.stall_start_s >= 0.0 && fo.stall_s > 0.0) {
          stall_from = *t0 + static_cast<TimeNs>(fo.stall_start_s * 1e9);
          stall_to = stall_from + static_cast<TimeNs>(fo.stall_s * 1e9);
        }
      }
      if (pass + 1 < loops && t_data >= t_first + period) break;  // the next pass starts there
      const TimeNs t = t_data + shift;
      if (const auto* imu_data = std::get_if<ImuSample>(&*m)) {
        ImuSample imu_shifted = *imu_data;
        imu_shifted.t_ns = t;
        const ImuSample* imu = &imu_shifted;
        auto bytes = lcm_io::encode(lcm_io::to_lcm(*imu));
        const TimeNs d = delay();
        const bool dup = fo.duplicate_imu > 0.0 && U(rng) < fo.duplicate_imu;
        enqueue(t, ch.imu, "imu", bytes, true, d);
        if (dup) {
          enqueue(t, ch.imu, "imu", std::move(bytes), false, d);  // published right after the original
          ++duplicated;
        }
        if (malformed_at.count(t_data)) add_malformed(t);
      } else if (const auto* r = std::get_if<RotorSample>(&*m)) {
        RotorSample shifted = *r;
        shifted.t_ns = t;
        enqueue(t, ch.rotors, "rotors", lcm_io::encode(lcm_io::to_lcm(shifted, rotor_unit)), true, delay());
      } else if (const auto* th = std::get_if<ThrustSample>(&*m)) {
        ThrustSample shifted = *th;
        shifted.t_ns = t;
        enqueue(t, ch.thrust, "thrust", lcm_io::encode(lcm_io::to_lcm(shifted)), true, delay());
      } else if (const auto* f = std::get_if<ImageFrame>(&*m)) {
        for (const auto& [cam_id, g] : p->images) {
          const std::size_t k = image_index[cam_id]++;
          const std::string stream = "cam" + std::to_string(cam_id);
          if (t_data >= stall_from && t_data < stall_to) {
            ++stall_images[stream];
            if (!stalled) ++camera_stalls;
            stalled = true;
            continue;
          }
          if (fo.drop_images > 0.0 && k >= 10 && k + 1 < image_count[cam_id] && U(rng) < fo.drop_images) {
            ++dropped[stream];
            continue;
          }
          if (g.empty()) {
            ++unreadable;
            for (const auto& ref : f->images)
              if (ref.cam_id == cam_id) spdlog::warn("{}: unreadable image, not published", ref.path);
            continue;
          }
          const image_t msg = lcm_io::make_image(t, cam_id, g.cols, g.rows, g.data, g.step[0]);
          enqueue(t, cam_id == 0 ? ch.cam0 : ch.cam1, stream, lcm_io::encode(msg), true, delay());
        }
      }
      send_until(t);
      if (bar && imu_last > t_start)
        bar->update((pass + std::clamp(ns_to_s(t_data - t_start) / ns_to_s(imu_last - t_start), 0.0, 1.0)) / loops);
    }
  }
  send_until(INT64_MAX);
  if (bar) bar->finish();

  report["published"] = published;
  report["faults"] = {{"images_dropped", dropped},
                      {"imu_duplicated", duplicated},
                      {"reordered_arrivals", reordered},
                      {"late", late},
                      {"malformed", malformed},
                      {"stall_images", stall_images},
                      {"camera_stalls", camera_stalls}};
  report["images_unreadable"] = unreadable;
  report["loops"] = loops;
  report["camera_published"] = !opt.no_camera;
  if (!opt.fast) report["max_lag_ms"] = max_lag_ms;
  report["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return report;
}

}  // namespace vid::replay
