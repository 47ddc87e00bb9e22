#include "vid_system/prefetch.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <ctime>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "frontend/image_decode.h"

namespace vid::system {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// CPU time of the calling thread [ms].
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

}  // namespace

Prefetcher::Prefetcher(io::DatasetReader& reader, const PrefetchOptions& options) : reader_(reader), opt_(options) {
  if (opt_.capacity == 0) opt_.capacity = 1;
  if (opt_.decode_threads <= 0) return;
  threads_.emplace_back([this] { read_loop(); });
  for (int i = 0; i < opt_.decode_threads; ++i) threads_.emplace_back([this] { decode_loop(); });
}

Prefetcher::~Prefetcher() { stop(); }

void Prefetcher::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cancel_ = true;
  }
  cv_.notify_all();
  for (auto& t : threads_)
    if (t.joinable()) t.join();
}

void Prefetcher::lower_priority() const {
  if (opt_.background_nice <= 0) return;
  // Per-thread nice value (Linux): applies to this background thread only. Best effort.
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, tid);
  if (errno == 0) (void)setpriority(PRIO_PROCESS, tid, std::min(19, now + opt_.background_nice));
}

std::optional<Prefetched> Prefetcher::read_one() {
  if (window_ended_) return std::nullopt;
  while (auto m = reader_.next()) {
    const TimeNs t = stamp_of(*m);
    if (!t0_) {
      t0_ = t;
      t_start_ = t + static_cast<TimeNs>(opt_.start_s * 1e9);
      t_end_ = opt_.end_s >= 0.0 ? t + static_cast<TimeNs>(opt_.end_s * 1e9) : INT64_MAX;
    }
    if (t < t_start_) continue;
    if (t > t_end_) break;
    Prefetched p;
    p.m = std::move(*m);
    p.t0 = *t0_;
    return p;
  }
  window_ended_ = true;
  return std::nullopt;
}

void Prefetcher::decode(Prefetched& p) {
  const auto* f = std::get_if<ImageFrame>(&p.m);
  if (!f) return;
  const auto t_wall = Clock::now();
  const double t_cpu = thread_cpu_ms();
  for (const auto& ref : f->images)
    if (ref.cam_id <= 1)
      p.images.emplace_back(ref.cam_id, decode_gray8(ref.path, nullptr, opt_.image_bits[ref.cam_id == 1 ? 1 : 0]));
  p.decode_ms = ms_since(t_wall);
  p.decode_cpu_ms = thread_cpu_ms() - t_cpu;
}

void Prefetcher::read_loop() {
  lower_priority();
  try {
    while (auto p = read_one()) {
      const bool frame = std::holds_alternative<ImageFrame>(p->m);
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [&] {
        return cancel_ || (queue_.size() < opt_.capacity &&
                           (!frame || opt_.max_frames == 0 || frames_queued_ < opt_.max_frames));
      });
      if (cancel_) break;
      auto slot = std::make_unique<Slot>();
      slot->p = std::move(*p);
      slot->ready = !frame;
      if (frame) {
        jobs_.push_back(slot.get());
        ++frames_queued_;
      }
      queue_.push_back(std::move(slot));
      cv_.notify_all();
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  reader_done_ = true;
  cv_.notify_all();
}

void Prefetcher::decode_loop() {
  lower_priority();
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    cv_.wait(lock, [&] { return cancel_ || reader_done_ || !jobs_.empty(); });
    if (cancel_ || jobs_.empty()) return;  // cancelled, or the reader ended and nothing is left
    Slot* slot = jobs_.front();
    jobs_.pop_front();
    lock.unlock();
    try {
      decode(slot->p);  // the slot stays in queue_ (not taken before ready), so it is ours alone
    } catch (...) {
      slot->error = std::current_exception();
    }
    lock.lock();
    slot->ready = true;
    ++stats_.frames_decoded;
    stats_.decode_cpu_ms += slot->p.decode_cpu_ms;
    cv_.notify_all();
  }
}

void Prefetcher::wait_ready() {
  if (threads_.empty()) return;
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] {
    const bool full = queue_.size() >= opt_.capacity || (opt_.max_frames > 0 && frames_queued_ >= opt_.max_frames);
    return reader_done_ || (full && jobs_.empty());
  });
}

std::optional<Prefetched> Prefetcher::next() {
  if (threads_.empty()) {  // inline: read and decode on the caller's thread
    if (cancel_) return std::nullopt;
    auto p = read_one();
    if (p && std::holds_alternative<ImageFrame>(p->m)) {
      decode(*p);
      ++stats_.frames_decoded;
      stats_.decode_cpu_ms += p->decode_cpu_ms;
    }
    return p;
  }
  const auto t_wait = Clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] { return cancel_ || (queue_.empty() ? reader_done_ : queue_.front()->ready); });
  stats_.consumer_wait_ms += ms_since(t_wait);
  if (queue_.empty() || !queue_.front()->ready) {  // the end, or stopped with nothing decoded
    if (error_ && !cancel_) std::rethrow_exception(error_);
    return std::nullopt;
  }
  std::unique_ptr<Slot> slot = std::move(queue_.front());
  queue_.pop_front();
  if (std::holds_alternative<ImageFrame>(slot->p.m)) --frames_queued_;
  cv_.notify_all();
  if (slot->error) std::rethrow_exception(slot->error);
  return std::move(slot->p);
}

PrefetchStats Prefetcher::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace vid::system
