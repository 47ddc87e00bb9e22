#pragma once
/// @file frontend_params_yaml.h
/// @brief FrontendParams from YAML (strict: unknown keys are errors naming file and line).
/// Keys are the FrontendParams field names; enums are strings:
/// equalization: none|histogram|clahe, ransac: none|fundamental|two_point.

#include <filesystem>
#include <string>

#include "frontend/frontend_params.h"
#include "io/strict_yaml.h"

namespace vid {

/// @brief Read every present key of @p map over @p defaults; unknown keys throw ConfigError.
FrontendParams frontend_params_from_yaml(const io::YamlMap& map, FrontendParams defaults = {});

/// @brief Load a file whose root holds the keys, or whose root has a `frontend:` section.
FrontendParams load_frontend_params(const std::filesystem::path& path);
/// @brief Every field as YAML, one readable block (frontend_params_from_yaml reads it back).
std::string to_yaml(const FrontendParams& params);
/// @brief Field-wise equality over the same tables that parse and print.
bool operator==(const FrontendParams& a, const FrontendParams& b);

}  // namespace vid
