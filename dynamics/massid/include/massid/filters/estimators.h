#pragma once
/// @file estimators.h
/// @brief The model-based methods of the study ("ekf", "ukf", "msckf", "swls", and "vio": the
/// VIO's estimator core, vio_filter.h) as MassEstimator adapters over the filters of this folder.

#include <memory>
#include <string>
#include <vector>

#include "massid/estimator.h"
#include "massid/filters/tuning.h"

namespace vid::massid {

/// @brief Names of the model-based methods, in report order.
std::vector<std::string> model_based_methods();

/// @brief Create a model-based estimator. @throws std::invalid_argument on an unknown name
std::unique_ptr<MassEstimator> make_model_based_estimator(const std::string& method,
                                                          const ModelBasedTuning& tuning = {});

}  // namespace vid::massid
