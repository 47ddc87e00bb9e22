/// @file test_parameters_doc.cpp
/// @brief docs/parameters.md (generated from the headers by scripts/gen_parameters.py) states
/// the defaults the loaders really print: every key of to_yaml(EstimatorParams{}) and
/// to_yaml(FrontendParams{}) is in the reference, with an equal default (issue #25). The
/// generator reads the default initializers as text; this catches any it would misread.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "frontend/frontend_params_yaml.h"
#include "vio_core/estimator_params_yaml.h"

namespace vid {
namespace {

/// @brief key -> default of the reference's table rows "| `key` | type | `default` | doc |".
std::map<std::string, std::string> documented_defaults() {
  std::ifstream in(std::filesystem::path(VID_SOURCE_DIR) / "docs" / "parameters.md");
  std::map<std::string, std::string> out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const std::size_t k0 = 3, k1 = line.find('`', k0);
    const std::size_t d0 = line.find("| `", k1 + 2);  // past the type column
    if (k1 == std::string::npos || d0 == std::string::npos) continue;
    const std::size_t d1 = line.find('`', d0 + 3);
    out[line.substr(k0, k1 - k0)] = line.substr(d0 + 3, d1 - d0 - 3);
  }
  return out;
}

void expect_documented(const std::string& yaml, const std::map<std::string, std::string>& doc) {
  std::istringstream lines(yaml);
  int keys = 0;
  for (std::string line; std::getline(lines, line); ++keys) {
    const std::string key = line.substr(0, line.find(':'));
    const std::string value = line.substr(line.find(':') + 2);
    const auto it = doc.find(key);
    ASSERT_NE(it, doc.end()) << key << " is not in docs/parameters.md";
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    if (end != value.c_str() && *end == '\0') {
      EXPECT_EQ(std::stod(it->second), number) << key;  // 1.0e-3 and 0.001 are one default
    } else {
      EXPECT_EQ(it->second, value) << key;
    }
  }
  EXPECT_GT(keys, 30);
}

TEST(ParametersDoc, DefaultsAreWhatTheLoadersPrint) {
  const auto doc = documented_defaults();
  expect_documented(to_yaml(EstimatorParams{}), doc);
  expect_documented(to_yaml(FrontendParams{}), doc);
}

}  // namespace
}  // namespace vid
