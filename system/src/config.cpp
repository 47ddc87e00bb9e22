#include "vid_system/config.h"

#include <sstream>

#include <yaml-cpp/yaml.h>
#include <stdexcept>

#include "frontend/frontend_params_yaml.h"
#include "io/errors.h"
#include "io/kalibr.h"
#include "io/sensor_yaml.h"
#include "io/strict_yaml.h"
#include "vio_core/estimator_params_yaml.h"

namespace vid::system {

namespace fs = std::filesystem;

SystemConfig resolve_config(const std::optional<fs::path>& config, const io::DatasetCalibration& dataset) {
  SystemConfig cfg;
  cfg.sources["estimator"] = "defaults";
  cfg.sources["frontend"] = "defaults";
  cfg.cameras = dataset.cameras;
  cfg.imu = dataset.imu;
  cfg.rotor = dataset.rotor;
  cfg.vehicle = dataset.vehicle;
  if (!dataset.cameras.empty()) cfg.sources["cameras"] = "dataset camN/sensor.yaml";
  if (dataset.imu) cfg.sources["imu"] = "dataset imu0/sensor.yaml";
  if (dataset.rotor) cfg.sources["rotor"] = "dataset rotor0/sensor.yaml";
  if (dataset.vehicle) cfg.sources["vehicle"] = "dataset vehicle.yaml";

  std::optional<io::YamlMap> estimator_yaml;  // the keys the preset's estimator.yaml sets
  if (config) {
    fs::path dir = *config;
    fs::path estimator_file;
    if (fs::is_regular_file(*config)) {
      estimator_file = *config;
      dir = config->parent_path();
    } else if (fs::is_directory(*config)) {
      estimator_file = dir / "estimator.yaml";
    } else {
      throw io::ConfigError(config->string() + ": no such config file or folder");
    }
    if (fs::exists(estimator_file)) {
      cfg.estimator = load_estimator_params(estimator_file);
      cfg.sources["estimator"] = estimator_file.string();
      estimator_yaml = io::YamlMap::load_file(estimator_file);
      // Only an explicit `mode:` pins the mode; the struct default must not override auto-detection.
      if (estimator_yaml->has("mode")) cfg.preset_mode = cfg.estimator.mode;
    }
    if (const fs::path f = dir / "frontend.yaml"; fs::exists(f)) {
      cfg.frontend = load_frontend_params(f);
      cfg.sources["frontend"] = f.string();
    }
    if (const fs::path f = dir / "imu.yaml"; fs::exists(f)) {
      cfg.imu = io::load_kalibr_imu(f);
      cfg.sources["imu"] = f.string();
    }
    for (const char* name : {"camchain.yaml", "camchain-imucam.yaml"}) {
      if (const fs::path f = dir / name; fs::exists(f)) {
        cfg.cameras = io::load_kalibr_imucam(f);
        cfg.sources["cameras"] = f.string();
        break;
      }
    }
    if (const fs::path f = dir / "rotor_sensor.yaml"; fs::exists(f)) {
      cfg.rotor = io::load_rotor_yaml(f);
      cfg.sources["rotor"] = f.string();
    }
    if (const fs::path f = dir / "vehicle.yaml"; fs::exists(f)) {
      cfg.vehicle = io::load_vehicle_yaml(f);
      cfg.sources["vehicle"] = f.string();
    }
    // A folder that holds none of the preset files is a mistyped path, not "use defaults".
    bool any = false;
    for (const char* name : {"estimator.yaml", "frontend.yaml", "imu.yaml", "camchain.yaml", "camchain-imucam.yaml",
                             "rotor_sensor.yaml", "vehicle.yaml"})
      any = any || fs::exists(dir / name);
    if (!any)
      throw io::ConfigError(config->string() +
                            ": not a preset (no estimator.yaml, frontend.yaml, imu.yaml, camchain-imucam.yaml, "
                            "rotor_sensor.yaml or vehicle.yaml)");
  }

  // The IMU calibration is the source of truth for IMU noise; the vehicle for gravity. A value
  // the preset's estimator.yaml gives them too is replaced, and said so when it differs.
  const auto take = [&](const char* key, double& estimator_value, double value, const std::string& part) {
    if (estimator_yaml && estimator_yaml->has(key) && estimator_value != value) {
      std::ostringstream line;
      line << cfg.sources.at("estimator") << ": " << key << " " << estimator_value << " is replaced by "
           << cfg.sources.at(part) << "'s " << value << " (the " << part << " file owns it: remove the key)";
      cfg.overrides.push_back(line.str());
    }
    estimator_value = value;
  };
  if (cfg.imu) {
    take("gyro_noise_density", cfg.estimator.gyro_noise_density, cfg.imu->gyro_noise_density, "imu");
    take("gyro_random_walk", cfg.estimator.gyro_random_walk, cfg.imu->gyro_random_walk, "imu");
    take("accel_noise_density", cfg.estimator.accel_noise_density, cfg.imu->accel_noise_density, "imu");
    take("accel_random_walk", cfg.estimator.accel_random_walk, cfg.imu->accel_random_walk, "imu");
    if (cfg.imu->rate_hz > 0.0) take("imu_rate_hz", cfg.estimator.imu_rate_hz, cfg.imu->rate_hz, "imu");
  }
  if (cfg.vehicle) take("gravity", cfg.estimator.gravity, cfg.vehicle->gravity, "vehicle");
  return cfg;
}

std::string describe(const SystemConfig& cfg) {
  std::ostringstream os;
  // Parameters built in code (tests) name no file.
  const auto source = cfg.sources.find("estimator");
  os << "# estimator (" << (source != cfg.sources.end() ? source->second : "parameters") << ")\n"
     << to_yaml(cfg.estimator) << "\n";
  for (const auto& cam : cfg.cameras) os << "# cam" << cam.cam_id << "\n" << cam << "\n";
  if (cfg.imu) os << "# imu\n" << *cfg.imu << "\n";
  if (cfg.rotor) os << "# rotor\n" << *cfg.rotor << "\n";
  if (cfg.vehicle) os << "# vehicle\n" << *cfg.vehicle << "\n";
  return os.str();
}

namespace {
/// YAML as JSON: maps, lists, and scalars as integer, number, boolean or text (in that order).
nlohmann::json to_json(const YAML::Node& n) {
  if (n.IsMap()) {
    nlohmann::json o = nlohmann::json::object();
    for (const auto& kv : n) o[kv.first.as<std::string>()] = to_json(kv.second);
    return o;
  }
  if (n.IsSequence()) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& e : n) a.push_back(to_json(e));
    return a;
  }
  if (!n.IsScalar()) return nullptr;
  if (n.Tag() != "!") {  // unquoted: a number or boolean when it reads as one
    long long i = 0;
    double d = 0.0;
    bool b = false;
    if (YAML::convert<long long>::decode(n, i)) return i;
    if (YAML::convert<double>::decode(n, d)) return d;
    if (YAML::convert<bool>::decode(n, b)) return b;
  }
  return n.as<std::string>();
}

template <typename T>
nlohmann::json part(const T& value, const std::string& name) {
  std::ostringstream os;
  os << value;
  return to_json(io::YamlMap::parse_string(os.str(), name));
}
}  // namespace

nlohmann::json describe_json(const SystemConfig& cfg) {
  nlohmann::json j;
  j["estimator"] = to_json(io::YamlMap::parse_string(to_yaml(cfg.estimator), "estimator"));
  j["cameras"] = nlohmann::json::array();
  for (const auto& cam : cfg.cameras) j["cameras"].push_back(part(cam, "cam" + std::to_string(cam.cam_id)));
  if (cfg.imu) j["imu"] = part(*cfg.imu, "imu");
  if (cfg.rotor) j["rotor"] = part(*cfg.rotor, "rotor");
  if (cfg.vehicle) j["vehicle"] = part(*cfg.vehicle, "vehicle");
  return j;
}

SystemParams make_system_params(const SystemOptions& opt, const io::DatasetCalibration& calibration) {
  SystemParams p;
  p.config = resolve_config(opt.config, calibration);
  p.features = opt.features;
  p.out_dir = opt.out_dir;
  p.write_tracks = opt.write_tracks;
  p.truth_vehicle = calibration.vehicle;
  SystemConfig& cfg = p.config;
  const bool thrust_data = opt.has_rotor || opt.has_thrust;
  // Mode: the flag, else the preset's explicit `mode:`, else dynamics when thrust information exists.
  p.mode_source = "flag --mode";
  if (opt.mode) {
    cfg.estimator.mode = *opt.mode;
  } else if (cfg.preset_mode) {
    cfg.estimator.mode = *cfg.preset_mode;
    p.mode_source = cfg.sources.at("estimator");
  } else {
    cfg.estimator.mode = thrust_data ? PropagationMode::kDynamics : PropagationMode::kImu;
    p.mode_source = thrust_data ? "auto (rotor/thrust data present)" : "auto (no rotor/thrust data)";
  }
  if (opt.init) cfg.estimator.init_mode = *opt.init;
  const bool dynamics = cfg.estimator.mode == PropagationMode::kDynamics;
  if (dynamics && !thrust_data)
    throw std::runtime_error(opt.context +
                             ": dynamics mode needs rotor speeds (rotor0/) or thrust (thrust0/), and the dataset has "
                             "neither; run with --mode imu");
  // thrust0 is the measured thrust: with it, rotor speeds are not needed (nor their coefficients).
  p.ignore_rotor_speeds = opt.has_thrust && opt.has_rotor;
  const bool rotor_thrust = opt.has_rotor && !opt.has_thrust;
  if (dynamics && !cfg.vehicle)
    throw std::runtime_error(opt.context + ": dynamics mode needs vehicle.yaml with mass_kg" +
                             (rotor_thrust ? " and rotor_thrust_coefficients (for the rotor0/ speeds)" : "") +
                             " in the dataset or the --config preset");
  if (dynamics && rotor_thrust && cfg.vehicle->rotor_thrust_coefficients.empty()) {
    const std::string& source = cfg.sources.at("vehicle");
    throw std::runtime_error((source.rfind("dataset", 0) == 0 ? opt.context + ": vehicle.yaml" : source) +
                             ": no rotor_thrust_coefficients, which dynamics mode needs to turn the rotor0/ speeds "
                             "into thrust (or give thrust0/, or run with --mode imu)");
  }
  if (cfg.cameras.empty())
    throw std::runtime_error(opt.context + ": no camera calibration (camN/sensor.yaml or --config camchain.yaml)");
  return p;
}

}  // namespace vid::system
