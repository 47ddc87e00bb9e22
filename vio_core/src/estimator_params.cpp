/// @file estimator_params.cpp
/// @brief String conversion of the estimator enums.
#include "vio_core/estimator_params.h"

#include <stdexcept>

namespace vid {

std::string to_string(PropagationMode mode) {
  return mode == PropagationMode::kImu ? "imu" : "dynamics";
}

PropagationMode mode_from_string(const std::string& s) {
  if (s == "imu") return PropagationMode::kImu;
  if (s == "dynamics") return PropagationMode::kDynamics;
  throw std::invalid_argument("unknown propagation mode '" + s + "' (expected imu or dynamics)");
}

std::string to_string(ForceFrame frame) { return frame == ForceFrame::kBody ? "body" : "world"; }

ForceFrame force_frame_from_string(const std::string& s) {
  if (s == "body") return ForceFrame::kBody;
  if (s == "world") return ForceFrame::kWorld;
  throw std::invalid_argument("unknown force frame '" + s + "' (expected body or world)");
}

std::string to_string(InitMode mode) {
  switch (mode) {
    case InitMode::kStatic: return "static";
    case InitMode::kGroundTruth: return "groundtruth";
    case InitMode::kAuto: return "auto";
  }
  return "unknown";
}

InitMode init_mode_from_string(const std::string& s) {
  if (s == "static") return InitMode::kStatic;
  if (s == "groundtruth") return InitMode::kGroundTruth;
  if (s == "auto") return InitMode::kAuto;
  throw std::invalid_argument("unknown init mode '" + s + "' (expected auto, static or groundtruth)");
}

}  // namespace vid
