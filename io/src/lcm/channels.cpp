#include "io/lcm/channels.h"

#include <array>
#include <utility>

#include "io/errors.h"
#include "io/strict_yaml.h"

namespace vid::lcm_io {
namespace {

/// @brief One (key, member) table drives parse and print, so the two cannot drift apart.
constexpr std::array<std::pair<const char*, std::string ChannelNames::*>, 10> kKeys = {{
    {"imu", &ChannelNames::imu},
    {"cam0", &ChannelNames::cam0},
    {"cam1", &ChannelNames::cam1},
    {"rotors", &ChannelNames::rotors},
    {"thrust", &ChannelNames::thrust},
    {"state", &ChannelNames::state},
    {"force", &ChannelNames::force},
    {"status", &ChannelNames::status},
    {"state_lagged", &ChannelNames::state_lagged},
    {"force_lagged", &ChannelNames::force_lagged},
}};

}  // namespace

ChannelNames parse_channels(const io::YamlMap& m) {
  ChannelNames c;
  for (const auto& [key, member] : kKeys) {
    c.*member = m.get_string(key, c.*member);
    if ((c.*member).empty()) m.fail(key, "expected a non-empty channel name");
  }
  m.check_unknown();
  return c;
}

ChannelNames load_channels(const std::filesystem::path& yaml_file) {
  // An empty file means all defaults.
  return parse_channels(io::YamlMap::from_node(io::YamlMap::parse_file(yaml_file), yaml_file.string(), ""));
}

std::string print(const ChannelNames& c) {
  std::string out;
  for (const auto& [key, member] : kKeys) {
    out += key;
    out += ": ";
    out += c.*member;
    out += '\n';
  }
  return out;
}

}  // namespace vid::lcm_io
