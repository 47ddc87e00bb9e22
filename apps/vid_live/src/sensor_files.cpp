#include "live/sensor_files.h"

#include <stdexcept>

#include "io/sensor_yaml.h"

namespace vid::live {

namespace fs = std::filesystem;

fs::path sensor_root(const fs::path& dir) { return fs::is_directory(dir / "mav0") ? dir / "mav0" : dir; }

io::DatasetCalibration load_sensor_files(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": no such sensor folder");
  const fs::path root = sensor_root(dir);
  io::DatasetCalibration c;
  for (int i = 0;; ++i) {
    const fs::path cam = root / ("cam" + std::to_string(i)) / "sensor.yaml";
    if (!fs::exists(cam)) break;
    c.cameras.push_back(io::load_camera_yaml(cam, i));
  }
  if (fs::exists(root / "imu0" / "sensor.yaml")) c.imu = io::load_imu_yaml(root / "imu0" / "sensor.yaml");
  if (fs::exists(root / "rotor0" / "sensor.yaml")) c.rotor = io::load_rotor_yaml(root / "rotor0" / "sensor.yaml");
  if (fs::exists(root / "vehicle.yaml")) c.vehicle = io::load_vehicle_yaml(root / "vehicle.yaml");
  return c;
}

}  // namespace vid::live
