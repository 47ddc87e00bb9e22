// driver_common.h: what the peer drivers (openvins/ov_driver.cpp, vidfusion/vidfusion_driver.cpp)
// share for reading a VID-MSCKF dataset folder and writing their outputs. Header-only.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// Our code (no OpenVINS or VID-Fusion code in it), GPL-3.0-or-later like the two drivers that
// include it: each driver links a GPL-3 peer, so the programs as a whole are GPL-3. A benchmark
// tool only: not part of the VID-MSCKF build, libraries or binaries (see bench/peers/README.md).
//
// The including file defines PEER_DRIVER_NAME (a string literal, the program name that prefixes
// error messages) before including this header.
#pragma once

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <yaml-cpp/yaml.h>

#ifndef PEER_DRIVER_NAME
#error "define PEER_DRIVER_NAME (the program name) before including driver_common.h"
#endif

namespace peers {

namespace fs = std::filesystem;

[[noreturn]] inline void die(const std::string &msg) {
  std::cerr << PEER_DRIVER_NAME ": " << msg << "\n";
  std::exit(1);
}

// ------------------------------------------------------------------------ YAML calibration

// Our sensor.yaml files may begin with "%YAML:1.0" (OpenCV copies); yaml-cpp rejects that line.
inline YAML::Node load_yaml(const fs::path &p) {
  std::ifstream f(p);
  if (!f) die("cannot open " + p.string());
  std::stringstream ss;
  std::string line;
  bool first = true;
  while (std::getline(f, line)) {
    if (first && line.rfind("%YAML", 0) == 0) {
      first = false;
      continue;
    }
    first = false;
    ss << line << "\n";
  }
  try {
    return YAML::Load(ss.str());
  } catch (const std::exception &e) {
    die(p.string() + ": " + e.what());
  }
}

template <typename T> T req(const YAML::Node &n, const std::string &key, const fs::path &p) {
  if (!n[key]) die(p.string() + ": missing key '" + key + "'");
  return n[key].as<T>();
}

// ------------------------------------------------------------------------ CSV (docs/formats.md §1)

inline std::vector<std::string> split_csv(const std::string &line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string tok;
  while (std::getline(ss, tok, ',')) out.push_back(tok);
  return out;
}

// Rows of numbers of a CSV (# lines skipped); column 0 as int64 ns.
struct Row {
  int64_t ns;
  std::vector<double> v;
};
inline std::vector<Row> read_rows(const fs::path &csv, size_t min_cols) {
  std::ifstream f(csv);
  if (!f) die("cannot open " + csv.string());
  std::vector<Row> rows;
  std::string line;
  size_t ln = 0;
  while (std::getline(f, line)) {
    ++ln;
    if (line.empty() || line[0] == '#') continue;
    auto t = split_csv(line);
    if (t.size() < min_cols) die(csv.string() + ":" + std::to_string(ln) + ": need " + std::to_string(min_cols) + " columns");
    Row r;
    r.ns = std::stoll(t[0]);
    for (size_t i = 1; i < t.size(); ++i) r.v.push_back(std::stod(t[i]));
    rows.push_back(std::move(r));
  }
  return rows;
}

// imu0/data.csv: ns, w_x, w_y, w_z [rad/s], a_x, a_y, a_z [m/s^2] (# lines skipped).
struct ImuSample {
  int64_t ns;
  Eigen::Vector3d w, a;
};

inline std::vector<ImuSample> read_imu(const fs::path &csv) {
  std::vector<ImuSample> v;
  for (const Row &r : read_rows(csv, 7)) {
    ImuSample s;
    s.ns = r.ns;
    s.w = {r.v[0], r.v[1], r.v[2]};
    s.a = {r.v[3], r.v[4], r.v[5]};
    v.push_back(s);
  }
  return v;
}

// camN/data.csv: ns, file name (trailing '\r' / ' ' removed; # lines and short rows skipped).
inline std::vector<std::pair<int64_t, std::string>> read_frames(const fs::path &csv) {
  std::ifstream f(csv);
  if (!f) die("cannot open " + csv.string());
  std::vector<std::pair<int64_t, std::string>> v;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    auto t = split_csv(line);
    if (t.size() < 2) continue;
    std::string name = t[1];
    while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
    v.emplace_back(std::stoll(t[0]), name);
  }
  return v;
}

// DATASET or DATASET/mav0, whichever holds the sensor folders.
inline fs::path dataset_root(fs::path dataset) {
  if (fs::exists(dataset / "mav0")) dataset /= "mav0";
  return dataset;
}

// ------------------------------------------------------------------------ arguments / config keys

// "--set key=value" into overrides.
inline void parse_set(const std::string &kv, std::map<std::string, std::string> &overrides) {
  auto eq = kv.find('=');
  if (eq == std::string::npos) die("--set needs key=value");
  overrides[kv.substr(0, eq)] = kv.substr(eq + 1);
}

// Replace the value of key k in an ordered key list, or append (k, v).
inline void set_key(std::vector<std::pair<std::string, std::string>> &kvs, const std::string &k, const std::string &v) {
  for (auto &kv : kvs)
    if (kv.first == k) {
      kv.second = v;
      return;
    }
  kvs.emplace_back(k, v);
}

// ------------------------------------------------------------------------ outputs

// One trajectory_tum.txt line: "sec.nsec tx ty tz qx qy qz qw\n" (p_WI, q_WI).
inline std::string tum_line(int64_t ns, const Eigen::Vector3d &p, const Eigen::Quaterniond &q) {
  char line[256];
  std::snprintf(line, sizeof line, "%lld.%09lld %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                static_cast<long long>(ns / 1000000000LL), static_cast<long long>(ns % 1000000000LL), p.x(), p.y(),
                p.z(), q.x(), q.y(), q.z(), q.w());
  return line;
}

// Percentile p in [0, 1] (the sample at rank ceil(p (n-1))); NaN when empty.
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  size_t k = static_cast<size_t>(std::ceil(p * (v.size() - 1)));
  return v[std::min(k, v.size() - 1)];
}

inline double mean(const std::vector<double> &v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? std::nan("") : s / v.size();
}

// This process's resource use so far (ru_maxrss = peak RSS [kB]).
inline struct rusage self_rusage() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return ru;
}

// The last keys of summary.json, from "  \"wall_s\"" to the closing brace.
inline void write_summary_resources(std::ostream &js, double wall_s, const struct rusage &ru) {
  js << "  \"wall_s\": " << wall_s << ",\n  \"peak_rss_kb\": " << ru.ru_maxrss
     << ",\n  \"cpu_user_s\": " << ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec
     << ",\n  \"cpu_sys_s\": " << ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec << "\n}\n";
}

}  // namespace peers
