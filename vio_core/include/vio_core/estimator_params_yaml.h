#pragma once
/// @file estimator_params_yaml.h
/// @brief Strict YAML loading/printing of vid::EstimatorParams. Keys are the field names;
/// every key is optional (defaults from the struct); unknown keys, wrong types and invalid
/// enum values are io::ConfigErrors naming file, line and key. Library vio_core_config (over
/// vio_core and io's strict YAML reader), so that vio_core itself stays Eigen only.

#include <filesystem>
#include <ostream>
#include <string>

#include "io/errors.h"
#include "vio_core/estimator_params.h"

namespace vid {

/// @brief Load estimator settings from @p path (flat mapping of field names).
EstimatorParams load_estimator_params(const std::filesystem::path& path);
/// @brief Load from YAML text; @p name stands for the file in messages.
EstimatorParams load_estimator_params_string(const std::string& text, const std::string& name);
/// @brief Every field as YAML (load_estimator_params reads it back exactly).
std::string to_yaml(const EstimatorParams& params);

/// @brief Print as YAML (the exact configuration of a run).
std::ostream& operator<<(std::ostream& os, const EstimatorParams& params);
/// @brief Field-wise equality over the same tables that load and print (so a new field
/// caught by the drift guard in tests/vio_core/test_estimator_params_yaml.cpp is compared too).
bool operator==(const EstimatorParams& a, const EstimatorParams& b);

}  // namespace vid
