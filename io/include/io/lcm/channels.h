#pragma once
/// @file channels.h
/// @brief LCM channel names used by vid_live and vid_replay (configurable by a YAML file).

#include <filesystem>
#include <string>

namespace vid::io {
class YamlMap;
}

namespace vid::lcm_io {

/// @brief Channel names. The YAML file has any of the keys imu, cam0, cam1, rotors, thrust,
/// state, force, status, state_lagged, force_lagged (unknown keys are errors).
struct ChannelNames {
  std::string imu = "IMU";
  std::string cam0 = "CAM0";
  std::string cam1 = "CAM1";
  std::string rotors = "ROTORS";
  std::string thrust = "THRUST";
  std::string state = "VID_STATE";
  std::string force = "VID_FORCE";
  std::string status = "VID_STATUS";
  std::string state_lagged = "VID_STATE_LAGGED";  ///< vid_live --lag: the fixed-lag smoothed state
  std::string force_lagged = "VID_FORCE_LAGGED";  ///< ... and force

  bool operator==(const ChannelNames&) const = default;
};

/// @brief Channel names from a parsed map (missing keys keep defaults); throws
/// io::ConfigError naming the file and key at fault.
ChannelNames parse_channels(const io::YamlMap& m);
/// @brief Load channel names from a YAML file (an empty file = defaults).
ChannelNames load_channels(const std::filesystem::path& yaml_file);
/// @brief All channel names as a YAML block ("imu: IMU\n..."); parse_channels reads it back.
std::string print(const ChannelNames& c);

}  // namespace vid::lcm_io
