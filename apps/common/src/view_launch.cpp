/// @file view_launch.cpp
/// @brief Runs `vid-eval view` for --rerun (see app/view_launch.h).
#include "app/view_launch.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace vid::app {

namespace fs = std::filesystem;

namespace {

bool executable(const fs::path& p) { return ::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p); }

}  // namespace

std::optional<fs::path> find_vid_eval(const char* argv0) {
  if (const char* env = std::getenv("VID_EVAL"); env && *env) return executable(env) ? std::optional<fs::path>(env) : std::nullopt;
  if (const char* path = std::getenv("PATH")) {
    std::stringstream dirs(path);
    for (std::string dir; std::getline(dirs, dir, ':');)
      if (!dir.empty() && executable(fs::path(dir) / "vid-eval")) return fs::path(dir) / "vid-eval";
  }
  std::error_code ec;  // build/bin/vid_run -> .venv/bin/vid-eval of the repository
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  const fs::path self = ec ? fs::absolute(argv0) : exe;
  const fs::path venv = self.parent_path().parent_path().parent_path() / ".venv" / "bin" / "vid-eval";
  if (executable(venv)) return venv;
  return std::nullopt;
}

void run_vid_eval(const char* argv0, const std::vector<std::string>& args, const std::string& context) {
  const auto tool = find_vid_eval(argv0);
  if (!tool)
    throw std::runtime_error(context + ": vid-eval not found (set VID_EVAL, put it on PATH, or run scripts/setup.sh)");
  std::vector<std::string> argv = {tool->string()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargs;
  for (auto& a : argv) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, cargs[0], nullptr, nullptr, cargs.data(), environ) != 0)
    throw std::runtime_error(context + ": cannot start " + argv[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(context + ": " + argv[0] + " " + (args.empty() ? "" : args[0]) +
                             " failed (its message is above)");
}

void write_rerun_recording(const char* argv0, const fs::path& run_dir, const std::optional<fs::path>& dataset,
                           const fs::path& rrd) {
  std::vector<std::string> args = {"view", run_dir.string(), "--rrd", rrd.string()};
  if (dataset) {
    args.push_back("--dataset");
    args.push_back(dataset->string());
  }
  try {
    run_vid_eval(argv0, args, "--rerun");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + "; the run's outputs are kept");
  }
}

}  // namespace vid::app
