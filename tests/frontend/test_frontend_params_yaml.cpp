/// @file test_frontend_params_yaml.cpp
/// @brief FrontendParams as a typed parameter struct: parse(print(x)) == x, a changed field
/// compares unequal, and errors name file, line and key.

#include <gtest/gtest.h>

#include <sstream>

#include "frontend/frontend_params_yaml.h"

namespace vid {
namespace {

FrontendParams parse(const std::string& text) {
  return frontend_params_from_yaml(io::YamlMap::load_string(text, "f.yaml"));
}

TEST(FrontendParamsYaml, PrintParseRoundTripAndEquality) {
  FrontendParams p;
  p.num_features = 321;
  p.lk_epsilon = 0.1 + 0.2;
  p.ransac = RansacMode::kTwoPoint;
  p.equalization = Equalization::kHistogram;
  p.gyro_prediction = !p.gyro_prediction;
  EXPECT_TRUE(parse(to_yaml(p)) == p);
  EXPECT_EQ(to_yaml(parse(to_yaml(p))), to_yaml(p));
  EXPECT_FALSE(p == FrontendParams{});
  EXPECT_TRUE(parse("{}") == FrontendParams{});
  // Every printed key, changed alone (to a value that still validates), makes the structs
  // unequal: equality misses no field.
  std::istringstream lines(to_yaml(FrontendParams{}));
  int keys = 0;
  for (std::string line; std::getline(lines, line); ++keys) {
    const std::string key = line.substr(0, line.find(':'));
    const std::string value = line.substr(key.size() + 2);
    std::ostringstream changed;
    changed.precision(17);
    if (key == "equalization") changed << (value == "clahe" ? "none" : "clahe");
    else if (key == "ransac") changed << (value == "none" ? "fundamental" : "none");
    else if (key == "image_bit_depth") changed << 12;  // 0 (auto) or 9..16
    else if (value == "true" || value == "false") changed << (value == "true" ? "false" : "true");
    else if (value.find_first_of(".e") == std::string::npos) changed << std::stoi(value) + 2;  // keeps odd sizes odd
    else changed << (std::stod(value) == 0.0 ? 0.001 : std::stod(value) * 0.99);
    EXPECT_FALSE(parse(key + ": " + changed.str() + "\n") == FrontendParams{}) << key;
  }
  EXPECT_EQ(keys, 42);  // every FrontendParams field
}

TEST(FrontendParamsYaml, ErrorsNameFileLineAndKey) {
  auto error_of = [](const std::string& text) {
    try {
      parse(text);
    } catch (const io::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of("num_featurs: 3\n"), "f.yaml:1: unknown key 'num_featurs'");
  EXPECT_EQ(error_of("ransac: always\n"), "f.yaml:1: key 'ransac': expected none|fundamental|two_point, got 'always'");
  EXPECT_EQ(error_of("x: 1\nlk_window: 4\n"), "f.yaml:2: key 'lk_window': must be odd");
  EXPECT_EQ(error_of("image_bit_depth: 8\n"),
            "f.yaml:1: key 'image_bit_depth': must be 0 (auto) or in [9, 16] (significant bits of 16-bit images)");
}

}  // namespace
}  // namespace vid
