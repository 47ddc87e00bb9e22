#include "io/reader_options_yaml.h"

namespace vid::io {
namespace {

struct Flag {
  const char* key;
  bool ReaderOptions::*member;
};
const Flag kFlags[] = {
    {"drop_bad_timestamps", &ReaderOptions::drop_bad_timestamps},
    {"skip_missing_images", &ReaderOptions::skip_missing_images},
    {"read_images", &ReaderOptions::read_images},
    {"read_features", &ReaderOptions::read_features},
    {"read_groundtruth", &ReaderOptions::read_groundtruth},
};

}  // namespace

ReaderOptions load_reader_options(const YamlMap& map) {
  ReaderOptions o;
  for (const Flag& f : kFlags) o.*f.member = map.get_bool(f.key, o.*f.member);
  map.check_unknown();
  return o;
}

std::string to_yaml(const ReaderOptions& options) {
  std::string out;
  for (const Flag& f : kFlags) out += std::string(f.key) + ": " + (options.*f.member ? "true" : "false") + "\n";
  return out;
}

std::ostream& operator<<(std::ostream& os, const ReaderOptions& options) { return os << to_yaml(options); }

bool operator==(const ReaderOptions& a, const ReaderOptions& b) {
  for (const Flag& f : kFlags) {
    if (a.*f.member != b.*f.member) return false;
  }
  return true;
}

}  // namespace vid::io
