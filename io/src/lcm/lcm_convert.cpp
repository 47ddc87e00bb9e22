#include "io/lcm/lcm_convert.h"

#include <cmath>
#include <cstring>
#include <optional>

namespace vid::lcm_io {

namespace {
bool finite3(const double* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

/// Walks the length fields of an LCM payload. lcm-gen's decoders trust them: an array is
/// allocated before its bytes are checked, and a string length of INT32_MIN overflows.
class LengthWalk {
 public:
  LengthWalk(const void* data, std::size_t size) : p_(static_cast<const std::uint8_t*>(data)), size_(size) {}
  /// Skip @p n fixed bytes.
  void skip(std::int64_t n) { at_ += n; }
  /// Read an int32 length field; nullopt (and stop) when cut off: the decoder rejects that.
  std::optional<std::int64_t> length() {
    if (!ok() || at_ + 4 > static_cast<std::int64_t>(size_)) return stop();
    const std::uint8_t* b = p_ + at_;
    at_ += 4;
    return static_cast<std::int32_t>((std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) |
                                     (std::uint32_t{b[2]} << 8) | std::uint32_t{b[3]});
  }
  /// Check an array of @p count elements of at least @p bytes each; false records why.
  bool array(std::optional<std::int64_t> count, std::int64_t bytes, const char* field) {
    if (!count) return false;
    if (*count < 0 || *count * bytes > static_cast<std::int64_t>(size_) - at_) {
      why_ = std::string(field) + " " + std::to_string(*count) + " exceeds the payload";
      return false;
    }
    return true;
  }
  /// Check and skip a string (length with its NUL, at least 1).
  bool string(const char* field) {
    const auto len = length();
    if (len && *len < 1) why_ = std::string(field) + ": string length " + std::to_string(*len);
    if (!len || *len < 1 || !array(len, 1, field)) return false;
    at_ += *len;
    return true;
  }
  const std::string& why() const { return why_; }

 private:
  bool ok() const { return why_.empty() && !stopped_; }
  std::nullopt_t stop() {
    stopped_ = true;
    return std::nullopt;
  }
  const std::uint8_t* p_;
  std::size_t size_;
  std::int64_t at_ = 8;  // after the fingerprint
  bool stopped_ = false;
  std::string why_;
};
}  // namespace

namespace detail {
// Field order follows io/lcm/*.lcm; types without strings or arrays need no check.
std::string check_array_lengths(const std::string& type_name, const void* data, std::size_t size) {
  LengthWalk w(data, size);
  if (type_name == "image_t") {  // timestamp, camera_id, width, height, encoding, size, data[size]
    w.skip(8 + 12);
    if (w.string("encoding")) w.array(w.length(), 1, "size");
  } else if (type_name == "rotor_speeds_t") {  // timestamp, count, speeds[count], unit
    w.skip(8);
    const auto count = w.length();
    if (w.array(count, 8, "count")) {
      w.skip(*count * 8);
      w.string("unit");
    }
  } else if (type_name == "status_t") {  // timestamp, status, 3 strings, reinit_count, n, names[n], values[n]
    w.skip(8 + 1);
    if (w.string("status_text") && w.string("message") && w.string("flight_phase")) {
      w.skip(4);
      const auto n = w.length();
      // each counter: a name (4-byte length, at least its NUL) and an 8-byte value
      if (w.array(n, 13, "num_counters")) {
        for (std::int64_t i = 0; i < *n && w.string("counter_names"); ++i) {
        }
      }
    }
  }
  return w.why();
}
}  // namespace detail

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
    case Health::kNoCamera: return "no_camera";
  }
  return "unknown";
}

}  // namespace vid::lcm_io
