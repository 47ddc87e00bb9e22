#include "app/cli.h"

#include <fmt/format.h>

#include <filesystem>

#include "vid_version/version.h"

namespace vid::app {

std::optional<int> parse_cli(CLI::App& app, int argc, char** argv) {
  if (argc > 0) app.set_version_flag("--version", version_line(std::filesystem::path(argv[0]).filename().string()));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help / --version: printed, exit 0
    throw UsageError(std::string(e.what()) + " (see --help)");
  }
  return std::nullopt;
}

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

}  // namespace vid::app
