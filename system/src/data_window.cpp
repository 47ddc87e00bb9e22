#include "vid_system/data_window.h"

#include <algorithm>
#include <fstream>
#include <string>

#include "vid_system/usage_error.h"

namespace vid::system {

namespace fs = std::filesystem;

std::optional<TimeNs> last_timestamp(const fs::path& csv) {
  std::ifstream f(csv, std::ios::binary | std::ios::ate);
  if (!f) return std::nullopt;
  const std::streamoff size = f.tellg();
  const std::streamoff back = std::min<std::streamoff>(size, 4096);
  f.seekg(size - back);
  std::string tail(static_cast<std::size_t>(back), '\0');
  f.read(tail.data(), back);
  std::size_t end = tail.find_last_not_of("\r\n ");
  if (end == std::string::npos) return std::nullopt;
  const std::size_t start = tail.rfind('\n', end);
  const std::string line = tail.substr(start == std::string::npos ? 0 : start + 1, end + 1);
  try {
    return static_cast<TimeNs>(std::stoll(line.substr(0, line.find(','))));
  } catch (...) {
    return std::nullopt;
  }
}

double data_span_s(const fs::path& dataset, const io::ReaderOptions& options) {
  io::DatasetReader probe(dataset, options);
  const auto first = probe.next();
  const auto last = last_timestamp(probe.mav0() / "imu0" / "data.csv");
  if (!first || !last) return 0.0;
  return std::max(0.0, ns_to_s(*last - stamp_of(*first)));
}

void check_dataset_window(const fs::path& dataset, const io::ReaderOptions& options, double start_s,
                          std::optional<double> end_s) {
  if (start_s == 0.0 && !end_s) return;  // the whole dataset: nothing to check, nothing to read
  check_window(start_s, end_s, data_span_s(dataset, options), dataset.string());
}

}  // namespace vid::system
