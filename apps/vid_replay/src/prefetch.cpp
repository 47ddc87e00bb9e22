#include "replay/prefetch.h"

#include "frontend/image_decode.h"

namespace vid::replay {

Prefetcher::Prefetcher(io::DatasetReader& reader, double start_s, double end_s, std::size_t capacity)
    : reader_(reader), start_s_(start_s), end_s_(end_s), capacity_(capacity), thread_([this] { run(); }) {}

Prefetcher::~Prefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cancel_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void Prefetcher::run() {
  try {
    std::optional<TimeNs> t0;
    TimeNs t_start = 0, t_end = INT64_MAX;
    while (auto m = reader_.next()) {
      const TimeNs t = stamp_of(*m);
      if (!t0) {
        t0 = t;
        t_start = t + static_cast<TimeNs>(start_s_ * 1e9);
        if (end_s_ >= 0.0) t_end = t + static_cast<TimeNs>(end_s_ * 1e9);
      }
      if (t < t_start) continue;
      if (t > t_end) break;
      Prefetched p{std::move(*m), *t0, {}};
      if (const auto* f = std::get_if<ImageFrame>(&p.m))
        for (const auto& ref : f->images)
          if (ref.cam_id <= 1) p.images.emplace_back(ref.cam_id, decode_gray8(ref.path));
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [&] { return queue_.size() < capacity_ || cancel_; });
      if (cancel_) return;
      queue_.push_back(std::move(p));
      cv_.notify_all();
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  done_ = true;
  cv_.notify_all();
}

void Prefetcher::wait_ready() {
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] { return queue_.size() >= capacity_ || done_; });
}

std::optional<Prefetched> Prefetcher::next() {
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, [&] { return !queue_.empty() || done_; });
  if (queue_.empty()) {
    if (error_) std::rethrow_exception(error_);
    return std::nullopt;
  }
  Prefetched p = std::move(queue_.front());
  queue_.pop_front();
  cv_.notify_all();
  return p;
}

}  // namespace vid::replay
