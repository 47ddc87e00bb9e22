#include "vid_system/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace vid::system {

namespace {
bool terminal_and_not_ci() {
  const char* ci = std::getenv("CI");
  if (ci != nullptr && *ci != '\0' && std::string(ci) != "0" && std::string(ci) != "false") return false;
  return ::isatty(STDERR_FILENO) == 1;
}
}  // namespace

ProgressBar::ProgressBar(std::string label, double total)
    : label_(std::move(label)),
      total_(total > 0.0 ? total : 1.0),
      enabled_(terminal_and_not_ci()),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && !finished_) std::fputc('\n', stderr);
}

void ProgressBar::update(double done, const std::string& extra) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(done, extra);
}

void ProgressBar::finish(const std::string& extra) {
  if (!enabled_ || finished_) return;
  draw(total_, extra);
  std::fputc('\n', stderr);
  finished_ = true;
}

void ProgressBar::draw(double done, const std::string& extra) {
  const double frac = std::clamp(done / total_, 0.0, 1.0);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = frac > 1e-9 ? elapsed * (1.0 - frac) / frac : 0.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(std::lround(frac * kWidth));
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  std::fprintf(stderr, "\r%s [%s] %5.1f%%  %.0fs elapsed, ETA %.0fs  %s\033[K", label_.c_str(), bar.c_str(),
               100.0 * frac, elapsed, eta, extra.c_str());
  std::fflush(stderr);
}

}  // namespace vid::system
