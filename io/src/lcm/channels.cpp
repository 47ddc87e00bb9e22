#include "io/lcm/channels.h"

#include <yaml-cpp/yaml.h>

#include <map>

#include "io/errors.h"

namespace vid::lcm_io {

ChannelNames load_channels(const std::filesystem::path& yaml_file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_file.string());
  } catch (const YAML::Exception& e) {
    throw io::ConfigError(yaml_file.string() + ": " + e.what());
  }
  ChannelNames c;
  if (!root || root.IsNull()) return c;
  if (!root.IsMap()) throw io::ConfigError(yaml_file.string() + ": expected a map of channel names");
  const std::map<std::string, std::string*> keys = {{"imu", &c.imu},       {"cam0", &c.cam0},   {"cam1", &c.cam1},
                                                    {"rotors", &c.rotors}, {"thrust", &c.thrust}, {"state", &c.state},
                                                    {"force", &c.force},   {"status", &c.status}};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    auto it = keys.find(key);
    if (it == keys.end()) throw io::ConfigError(yaml_file.string() + ": key '" + key + "': unknown channel key");
    if (!kv.second.IsScalar() || kv.second.as<std::string>().empty())
      throw io::ConfigError(yaml_file.string() + ": key '" + key + "': expected a non-empty channel name");
    *it->second = kv.second.as<std::string>();
  }
  return c;
}

}  // namespace vid::lcm_io
