#pragma once
/// @file manifest.h
/// @brief Writer of a study dataset's DIR/manifest.yaml (read back by read_dataset_index in
/// run_data.h).

#include <filesystem>
#include <string>
#include <vector>

#include "massid/run_data.h"

namespace vid::massid::gen {

/// @brief Write DIR/manifest.yaml: format tag, the generator settings (YAML text, embedded as
/// the `generator` map; may be empty) and every run's RunInfo under `runs`.
/// @throws std::runtime_error naming the file when it cannot be written
void write_manifest(const std::filesystem::path& dir, const std::string& generator_yaml,
                    const std::vector<RunInfo>& runs);

}  // namespace vid::massid::gen
