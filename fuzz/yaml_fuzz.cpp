/// @file yaml_fuzz.cpp
/// @brief libFuzzer target of the YAML configuration loaders: strict_yaml (YamlMap), the
/// dataset's sensor.yaml / vehicle.yaml, Kalibr's imu and imucam chains, estimator settings
/// and reader options. io::ConfigError (which carries yaml-cpp's syntax errors) and
/// io::DatasetError are expected outcomes; anything else is a bug.
///
/// Input: byte 0 mod 8 picks the loader (so the digits '0'..'7' do); the rest is the file.

#include <string>

#include "fuzz_util.h"
#include "io/kalibr.h"
#include "io/reader_options_yaml.h"
#include "io/sensor_yaml.h"
#include "vio_core/estimator_params_yaml.h"

namespace io = vid::io;

namespace {

void load(int kind, const std::filesystem::path& path, const std::string& text) {
  switch (kind) {
    case 0: (void)io::load_camera_yaml(path, 0); break;
    case 1: (void)io::load_imu_yaml(path); break;
    case 2: (void)io::load_rotor_yaml(path); break;
    case 3: (void)io::load_vehicle_yaml(path); break;
    case 4: (void)io::load_kalibr_imu(path); break;
    case 5: (void)io::load_kalibr_imucam(path); break;
    case 6: (void)vid::load_estimator_params_string(text, "estimator.yaml"); break;
    default: {  // reader options, plus the generic getters on whatever keys the map has
      const io::YamlMap map = io::YamlMap::load_string(text, "options.yaml");
      for (const std::string& key : map.keys()) {
        try { (void)map.get_doubles(key); } catch (const io::ConfigError&) {}
        try { (void)map.get_matrix4(key); } catch (const io::ConfigError&) {}
        try { (void)map.get_maps(key); } catch (const io::ConfigError&) {}
        try { (void)map.get_u64(key); } catch (const io::ConfigError&) {}
        try { (void)map.get_strings(key); } catch (const io::ConfigError&) {}
      }
      (void)io::load_reader_options(io::YamlMap::load_string(text, "options.yaml"));
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  const auto path = vid::fuzz::scratch_dir() / "config.yaml";
  vid::fuzz::write_file(path, text);
  try {
    load(data[0] % 8, path, text);
  } catch (const io::ConfigError&) {
  } catch (const io::DatasetError&) {
  }
  return 0;
}
