#pragma once
/// @file fuzz_util.h
/// @brief Helpers shared by the libFuzzer targets: a private scratch folder per process and
/// file writing, for parsers whose API takes paths.

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace vid::fuzz {

/// @brief A scratch folder unique to this process (parallel fuzzing jobs must not share it),
/// on tmpfs when available so the per-input file writes stay cheap.
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    const char* env = std::getenv("VID_FUZZ_SCRATCH");  // run.sh's folder, removed after the run
    const char* base = env ? env : std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
    std::string templ = std::string(base) + "/vid_fuzz_XXXXXX";
    if (mkdtemp(templ.data()) == nullptr) std::abort();
    std::atexit([] {  // libFuzzer exits normally at -max_total_time; a crash leaves it for study
      std::error_code ec;
      std::filesystem::remove_all(scratch_dir(), ec);
    });
    return std::filesystem::path(templ);
  }();
  return dir;
}

/// @brief Write @p bytes to @p path (creating its folder), replacing any previous content.
inline void write_file(const std::filesystem::path& path, std::string_view bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) std::abort();
}

}  // namespace vid::fuzz
