#pragma once
/// @file reader_options_yaml.h
/// @brief ReaderOptions as YAML (so a run records how it read its dataset) and back.

#include <ostream>
#include <string>

#include "io/dataset_reader.h"
#include "io/strict_yaml.h"

namespace vid::io {

/// @brief Read the options from a mapping (all keys optional; unknown keys are errors).
/// Keys: drop_bad_timestamps, skip_missing_images, read_images, read_features, read_groundtruth.
ReaderOptions load_reader_options(const YamlMap& map);
/// @brief Every option as YAML (load_reader_options reads it back).
std::string to_yaml(const ReaderOptions& options);
/// @brief Print as YAML.
std::ostream& operator<<(std::ostream& os, const ReaderOptions& options);
/// @brief Option-wise equality (same table as load and print).
bool operator==(const ReaderOptions& a, const ReaderOptions& b);

}  // namespace vid::io
