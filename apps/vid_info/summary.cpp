#include "summary.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

#include "io/sensor_yaml.h"

namespace vid::app {
namespace {

double rate_hz(const io::StreamStats& s) {
  const TimeNs span = s.last_ns - s.first_ns;
  return (s.count > 1 && span > 0) ? static_cast<double>(s.count - 1) / ns_to_s(span) : 0.0;
}

TimeNs first_of(const DatasetSummary& s) {
  TimeNs t0 = std::numeric_limits<TimeNs>::max();
  for (const auto& st : s.streams) t0 = std::min(t0, st.first_ns);
  return s.streams.empty() ? 0 : t0;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

}  // namespace

std::string summary_text(const DatasetSummary& s) {
  const TimeNs t0 = first_of(s);
  TimeNs t1 = t0;
  for (const auto& st : s.streams) t1 = std::max(t1, st.last_ns);
  std::string out = "dataset: " + s.mav0 + "\n";
  out += "time: first " + std::to_string(t0) + " ns, span " + fmt("%.3f", ns_to_s(t1 - t0)) + " s\n";
  char line[256];
  std::snprintf(line, sizeof(line), "%-28s %9s %10s %10s %10s %14s %10s %8s\n", "stream", "count", "rate[Hz]",
                "start[s]", "span[s]", "largest_gap[s]", "at[s]", "dropped");
  out += line;
  for (const auto& st : s.streams) {
    std::snprintf(line, sizeof(line), "%-28s %9zu %10.3f %10.3f %10.3f %14.6f %10.3f %8zu\n", st.name.c_str(),
                  st.count, rate_hz(st), ns_to_s(st.first_ns - t0), ns_to_s(st.last_ns - st.first_ns),
                  ns_to_s(st.largest_gap_ns), ns_to_s(st.largest_gap_at_ns - t0), st.dropped);
    out += line;
  }
  for (const auto& st : s.streams) {
    if (st.dropped_bad_timestamps > 0) {
      out += "  " + st.name + ": dropped " + std::to_string(st.dropped_bad_timestamps) + " rows with bad timestamps\n";
    }
    if (st.skipped_missing_images > 0) {
      out += "  " + st.name + ": skipped " + std::to_string(st.skipped_missing_images) + " missing images\n";
    }
  }
  const auto& c = s.calibration;
  out += "calibration:\n";
  out += "  imu0/sensor.yaml: ";
  out += c.imu ? "rate " + fmt("%g", c.imu->rate_hz) + " Hz, gyro noise " + fmt("%g", c.imu->gyro_noise_density) +
                     ", accel noise " + fmt("%g", c.imu->accel_noise_density) + "\n"
               : "not found\n";
  for (const auto& cam : c.cameras) {
    out += "  cam" + std::to_string(cam.cam_id) + "/sensor.yaml: " + std::to_string(cam.width) + "x" +
           std::to_string(cam.height) + " " + io::euroc_name(cam.distortion) + ", fu " + fmt("%g", cam.intrinsics[0]) +
           ", fv " + fmt("%g", cam.intrinsics[1]) + ", |p_IC| " + fmt("%.4f", cam.T_IC.translation().norm()) +
           " m\n";
  }
  if (c.cameras.empty()) out += "  camN/sensor.yaml: not found\n";
  out += "  rotor0/sensor.yaml: ";
  out += c.rotor ? std::to_string(c.rotor->count) + " rotors, unit " + c.rotor->unit + ", rate " +
                       fmt("%g", c.rotor->rate_hz) + " Hz\n"
                 : "not found\n";
  out += "  vehicle.yaml: ";
  out += c.vehicle ? "mass " + fmt("%g", c.vehicle->mass_kg) + " kg, gravity " + fmt("%g", c.vehicle->gravity) + ", " +
                         std::to_string(c.vehicle->rotor_thrust_coefficients.size()) + " thrust coefficients\n"
                   : "not found\n";
  return out;
}

std::string summary_json(const DatasetSummary& s) {
  nlohmann::ordered_json j;
  j["dataset"] = s.mav0;
  j["streams"] = nlohmann::ordered_json::array();
  for (const auto& st : s.streams) {
    j["streams"].push_back({{"name", st.name},
                            {"count", st.count},
                            {"rate_hz", rate_hz(st)},
                            {"first_ns", st.first_ns},
                            {"last_ns", st.last_ns},
                            {"span_s", ns_to_s(st.last_ns - st.first_ns)},
                            {"largest_gap_s", ns_to_s(st.largest_gap_ns)},
                            {"largest_gap_at_ns", st.largest_gap_at_ns},
                            {"dropped", st.dropped},
                            {"dropped_bad_timestamps", st.dropped_bad_timestamps},
                            {"skipped_missing_images", st.skipped_missing_images}});
  }
  const auto& c = s.calibration;
  nlohmann::ordered_json cal;
  cal["imu"] = c.imu ? nlohmann::ordered_json{{"rate_hz", c.imu->rate_hz},
                                              {"gyroscope_noise_density", c.imu->gyro_noise_density},
                                              {"gyroscope_random_walk", c.imu->gyro_random_walk},
                                              {"accelerometer_noise_density", c.imu->accel_noise_density},
                                              {"accelerometer_random_walk", c.imu->accel_random_walk}}
                     : nlohmann::ordered_json(nullptr);
  cal["cameras"] = nlohmann::ordered_json::array();
  for (const auto& cam : c.cameras) {
    cal["cameras"].push_back({{"cam_id", cam.cam_id},
                              {"resolution", {cam.width, cam.height}},
                              {"intrinsics", {cam.intrinsics[0], cam.intrinsics[1], cam.intrinsics[2], cam.intrinsics[3]}},
                              {"distortion_model", io::euroc_name(cam.distortion)},
                              {"rate_hz", cam.rate_hz}});
  }
  cal["rotor"] = c.rotor ? nlohmann::ordered_json{{"unit", c.rotor->unit},
                                                  {"count", c.rotor->count},
                                                  {"rate_hz", c.rotor->rate_hz}}
                         : nlohmann::ordered_json(nullptr);
  cal["vehicle"] = c.vehicle ? nlohmann::ordered_json{{"mass_kg", c.vehicle->mass_kg},
                                                      {"gravity", c.vehicle->gravity},
                                                      {"rotor_thrust_coefficients", c.vehicle->rotor_thrust_coefficients}}
                             : nlohmann::ordered_json(nullptr);
  j["calibration"] = cal;
  return j.dump(2) + "\n";
}

}  // namespace vid::app
