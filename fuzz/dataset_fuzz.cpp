/// @file dataset_fuzz.cpp
/// @brief libFuzzer target of vid::io::DatasetReader (io/src/dataset_reader.cpp,
/// stream_cursors.cpp and the sensor.yaml loaders it calls): a whole dataset folder per input.
/// io::DatasetError and io::ConfigError are expected outcomes; anything else is a bug.
///
/// Input: sections, each starting with a line "@NAME" (NAME: imu0, rotor0, thrust0, cam0, cam1,
/// feat0, force0, mass0, gt for the data.csv files; cam0.yaml, cam1.yaml, imu0.yaml, rotor0.yaml,
/// vehicle.yaml; opts: letters d s l w i f g toggle the ReaderOptions). Lines before the first
/// section go to imu0/data.csv. Images 1.png..3.png exist in cam0/data and cam1/data.

#include <map>
#include <string>
#include <string_view>

#include "fuzz_util.h"
#include "io/dataset_reader.h"

namespace {

namespace fs = std::filesystem;

const std::map<std::string, std::string, std::less<>>& files() {
  static const std::map<std::string, std::string, std::less<>> m = {
      {"imu0", "imu0/data.csv"},       {"rotor0", "rotor0/data.csv"},   {"thrust0", "thrust0/data.csv"},
      {"cam0", "cam0/data.csv"},       {"cam1", "cam1/data.csv"},       {"feat0", "feat0/data.csv"},
      {"force0", "force0/data.csv"},   {"mass0", "mass0/data.csv"},
      {"gt", "state_groundtruth_estimate0/data.csv"},
      {"cam0.yaml", "cam0/sensor.yaml"}, {"cam1.yaml", "cam1/sensor.yaml"}, {"imu0.yaml", "imu0/sensor.yaml"},
      {"rotor0.yaml", "rotor0/sensor.yaml"}, {"vehicle.yaml", "vehicle.yaml"}};
  return m;
}

/// The dataset folder, with the image files the camera rows may name.
fs::path dataset_root() {
  static const fs::path root = [] {
    const fs::path r = vid::fuzz::scratch_dir() / "seq" / "mav0";
    for (const char* cam : {"cam0", "cam1"}) {
      for (const char* img : {"1.png", "2.png", "3.png"}) vid::fuzz::write_file(r / cam / "data" / img, "");
    }
    return r;
  }();
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path root = dataset_root();
  for (const auto& [name, rel] : files()) fs::remove(root / rel);
  std::map<std::string, std::string> content;
  std::string section = "imu0", opts;
  std::string_view in(reinterpret_cast<const char*>(data), size);
  while (!in.empty()) {  // split into "@NAME" sections
    const std::size_t eol = in.find('\n');
    const std::string_view line = in.substr(0, eol == std::string_view::npos ? in.size() : eol + 1);
    in.remove_prefix(line.size());
    if (line.size() > 1 && line.front() == '@') {
      section = std::string(line.substr(1, line.find_first_of("\r\n") - 1));
      content[section];  // an empty section still makes an (empty) file
      continue;
    }
    if (section == "opts") opts += line;
    else content[section] += line;
  }
  for (const auto& [name, text] : content) {
    const auto f = files().find(name);
    if (f != files().end()) vid::fuzz::write_file(root / f->second, text);
  }
  vid::io::ReaderOptions o;
  auto has = [&](char c) { return opts.find(c) != std::string::npos; };
  o.drop_bad_timestamps = has('d');
  o.skip_missing_images = has('s');
  o.list_missing_images = has('l');
  o.gaps_as_warnings = has('w');
  o.read_images = !has('i');
  o.read_features = !has('f');
  o.read_groundtruth = !has('g');
  o.warn = [](const std::string&) {};
  try {
    vid::io::DatasetReader reader(root.parent_path(), o);
    for (int i = 0; i < 100000 && reader.next(); ++i) (void)reader.progress();
    (void)reader.stats();
  } catch (const vid::io::DatasetError&) {
  } catch (const vid::io::ConfigError&) {
  }
  return 0;
}
