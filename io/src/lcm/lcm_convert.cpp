#include "io/lcm/lcm_convert.h"

#include <cmath>
#include <cstring>

namespace vid::lcm_io {

namespace {
bool finite3(const double* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace

imu_t to_lcm(const ImuSample& s) {
  imu_t m;
  m.timestamp = s.t_ns;
  for (int i = 0; i < 3; ++i) {
    m.gyro[i] = s.gyro_I[i];
    m.accel[i] = s.accel_I[i];
  }
  return m;
}

ImuSample from_lcm(const imu_t& m, const std::string& channel) {
  if (!finite3(m.gyro) || !finite3(m.accel)) throw DecodeError(channel + ": imu_t with non-finite values");
  ImuSample s;
  s.t_ns = m.timestamp;
  s.gyro_I = Eigen::Vector3d(m.gyro[0], m.gyro[1], m.gyro[2]);
  s.accel_I = Eigen::Vector3d(m.accel[0], m.accel[1], m.accel[2]);
  return s;
}

rotor_speeds_t to_lcm(const RotorSample& s, const std::string& unit) {
  rotor_speeds_t m;
  m.timestamp = s.t_ns;
  m.count = static_cast<int32_t>(s.speeds.size());
  m.speeds = s.speeds;
  m.unit = unit;
  return m;
}

RotorSample from_lcm(const rotor_speeds_t& m, const std::string& channel, int expected_count,
                     const std::string& expected_unit) {
  if (expected_count > 0 && m.count != expected_count)
    throw DecodeError(channel + ": rotor_speeds_t has " + std::to_string(m.count) + " rotors, the rotor sensor has " +
                      std::to_string(expected_count));
  if (!expected_unit.empty() && m.unit != expected_unit)
    throw DecodeError(channel + ": rotor_speeds_t unit '" + m.unit + "', the rotor sensor's unit is '" + expected_unit + "'");
  for (double n : m.speeds)
    if (!std::isfinite(n)) throw DecodeError(channel + ": rotor_speeds_t with non-finite speeds");
  RotorSample s;
  s.t_ns = m.timestamp;
  s.speeds = m.speeds;
  return s;
}

thrust_t to_lcm(const ThrustSample& s) {
  thrust_t m;
  m.timestamp = s.t_ns;
  m.thrust = s.thrust_N;
  return m;
}

ThrustSample from_lcm(const thrust_t& m, const std::string& channel) {
  if (!std::isfinite(m.thrust)) throw DecodeError(channel + ": thrust_t with a non-finite thrust");
  return ThrustSample{m.timestamp, m.thrust};
}

image_t make_image(TimeNs t_ns, int camera_id, int width, int height, const std::uint8_t* pixels,
                   std::size_t row_stride) {
  image_t m;
  m.timestamp = t_ns;
  m.camera_id = camera_id;
  m.width = width;
  m.height = height;
  m.encoding = "mono8";
  m.size = width * height;
  m.data.resize(static_cast<std::size_t>(m.size));
  for (int r = 0; r < height; ++r)
    std::memcpy(m.data.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(width),
                pixels + static_cast<std::size_t>(r) * row_stride, static_cast<std::size_t>(width));
  return m;
}

void validate_image(const image_t& m, const std::string& channel, int num_cameras) {
  if (m.encoding != "mono8") throw DecodeError(channel + ": image_t encoding '" + m.encoding + "', expected mono8");
  if (m.width <= 0 || m.height <= 0)
    throw DecodeError(channel + ": image_t of size " + std::to_string(m.width) + "x" + std::to_string(m.height));
  if (static_cast<std::int64_t>(m.width) * m.height != static_cast<std::int64_t>(m.data.size()))
    throw DecodeError(channel + ": image_t holds " + std::to_string(m.data.size()) + " bytes for " +
                      std::to_string(m.width) + "x" + std::to_string(m.height) + " mono8");
  if (m.camera_id < 0 || m.camera_id >= num_cameras)
    throw DecodeError(channel + ": image_t camera_id " + std::to_string(m.camera_id) + " outside [0, " +
                      std::to_string(num_cameras) + ")");
}

std::string to_string(Health h) {
  switch (h) {
    case Health::kInitializing: return "initializing";
    case Health::kTracking: return "tracking";
    case Health::kDegraded: return "degraded";
    case Health::kDiverged: return "diverged";
  }
  return "unknown";
}

}  // namespace vid::lcm_io
