#pragma once
/// @file io_test_util.h
/// @brief Helpers of the io tests: scratch folders, whole-file edits, draining a reader.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/dataset_reader.h"
#include "io/errors.h"

namespace vid::io::test {

/// @brief The message of the io::ConfigError that @p f throws ("" when it throws none).
inline std::string config_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

/// @brief A fresh folder under the temp dir, removed at scope exit.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag = "") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("vid_io_" + std::string(info ? info->test_suite_name() : "x") + "_" +
             std::string(info ? info->name() : "x") + tag + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

inline std::vector<std::string> read_lines(const std::filesystem::path& p) {
  std::vector<std::string> lines;
  std::ifstream in(p, std::ios::binary);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

inline void write_lines(const std::filesystem::path& p, const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  write_text(p, text);
}

/// @brief Open and drain a dataset; the message of the DatasetError/ConfigError it throws,
/// or "" when it reads cleanly (any other exception propagates and fails the test).
inline std::string read_error(const std::filesystem::path& root, ReaderOptions options = {}) {
  try {
    DatasetReader reader(root, options);
    while (reader.next()) {
    }
  } catch (const DatasetError& e) {
    return e.what();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace vid::io::test
