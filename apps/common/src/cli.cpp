#include "app/cli.h"

#include <filesystem>

#include "vid_version/version.h"

namespace vid::app {

std::optional<int> parse_cli(CLI::App& app, int argc, char** argv) {
  if (argc > 0) app.set_version_flag("--version", version_line(std::filesystem::path(argv[0]).filename().string()));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help / --version: printed, exit 0
    throw system::UsageError(std::string(e.what()) + " (see --help)");
  }
  return std::nullopt;
}

}  // namespace vid::app
