#include "vid_system/usage_error.h"

#include <fmt/format.h>

namespace vid::system {

void check_window(double start_s, std::optional<double> end, double span_s, const std::string& data) {
  const std::string span = fmt::format("{}: the data span 0 to {:.3f} s", data, span_s);
  if (!(start_s >= 0.0)) throw UsageError(fmt::format("--start {}: negative ({})", start_s, span));
  if (start_s >= span_s) throw UsageError(fmt::format("--start {}: past the end of the data ({})", start_s, span));
  if (!end) return;  // to the end
  const double end_s = *end;
  if (end_s <= start_s)
    throw UsageError(fmt::format("--end {}: not after --start {}, the selection is empty ({})", end_s, start_s, span));
  // A small margin: --end is often a rounded duration of the recording.
  if (end_s > span_s + 1.0) throw UsageError(fmt::format("--end {}: past the end of the data ({})", end_s, span));
}

}  // namespace vid::system
