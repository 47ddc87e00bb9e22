#include "frontend/frontend_params_yaml.h"

#include <array>
#include <sstream>
#include <string>
#include <utility>

#include "io/number_format.h"

namespace vid {

namespace {

// One table per field type drives parse, print and ==, so the three cannot drift apart.
template <typename T>
struct Field {
  const char* key;
  T FrontendParams::*member;
};
#define VID_FIELD(name) {#name, &FrontendParams::name}
const Field<int> kInts[] = {
    VID_FIELD(num_features),
    VID_FIELD(grid_cols),
    VID_FIELD(grid_rows),
    VID_FIELD(fast_threshold),
    VID_FIELD(fast_threshold_min),
    VID_FIELD(border_px),
    VID_FIELD(detect_cell_retry_frames),
    VID_FIELD(detect_min_missing),
    VID_FIELD(clahe_tile),
    VID_FIELD(lk_levels),
    VID_FIELD(lk_window),
    VID_FIELD(lk_max_iterations),
    VID_FIELD(lk_predicted_max_iterations),
    VID_FIELD(template_half),
    VID_FIELD(template_iterations),
    VID_FIELD(ransac_max_iterations),
    VID_FIELD(stereo_lk_levels),
    VID_FIELD(stereo_track_lk_levels),
    VID_FIELD(stereo_retry_frames),
    VID_FIELD(image_bit_depth),
};
const Field<double> kDoubles[] = {
    VID_FIELD(min_distance_px),
    VID_FIELD(fast_noise_factor),
    VID_FIELD(clahe_clip_limit),
    VID_FIELD(lk_epsilon),
    VID_FIELD(lk_predicted_epsilon),
    VID_FIELD(lk_min_eigen),
    VID_FIELD(fb_check_px),
    VID_FIELD(template_epsilon_px),
    VID_FIELD(template_min_zncc),
    VID_FIELD(template_max_shift_px),
    VID_FIELD(ransac_threshold_px),
    VID_FIELD(ransac_confidence),
    VID_FIELD(stereo_epipolar_px),
    VID_FIELD(stereo_fb_check_px),
    VID_FIELD(stereo_max_disparity_px),
    VID_FIELD(stereo_min_depth_m),
};
const Field<bool> kBools[] = {
    VID_FIELD(template_refinement),
    VID_FIELD(direct_alignment),
    VID_FIELD(stereo),
    VID_FIELD(gyro_prediction),
};
#undef VID_FIELD

constexpr std::array<std::pair<const char*, Equalization>, 3> kEqualization = {
    {{"none", Equalization::kNone}, {"histogram", Equalization::kHistogram}, {"clahe", Equalization::kClahe}}};
constexpr std::array<std::pair<const char*, RansacMode>, 3> kRansac = {
    {{"none", RansacMode::kNone}, {"fundamental", RansacMode::kFundamental}, {"two_point", RansacMode::kTwoPoint}}};

template <typename E, std::size_t N>
E read_enum(const io::YamlMap& m, const char* key, const std::array<std::pair<const char*, E>, N>& names, E value) {
  if (!m.has(key)) {
    m.accept(key);
    return value;
  }
  const std::string s = m.get_string(key);
  std::string choices;
  for (const auto& [name, e] : names) {
    if (s == name) return e;
    if (!choices.empty()) choices += '|';
    choices += name;
  }
  m.fail(key, "expected " + choices + ", got '" + s + "'");
}

template <typename E, std::size_t N>
const char* enum_name(const std::array<std::pair<const char*, E>, N>& names, E value) {
  for (const auto& [name, e] : names) {
    if (e == value) return name;
  }
  return "?";
}

}  // namespace

FrontendParams frontend_params_from_yaml(const io::YamlMap& m, FrontendParams p) {
  for (const auto& f : kInts) p.*f.member = m.get_int(f.key, p.*f.member);
  for (const auto& f : kDoubles) p.*f.member = m.get_double(f.key, p.*f.member);
  for (const auto& f : kBools) p.*f.member = m.get_bool(f.key, p.*f.member);
  p.equalization = read_enum(m, "equalization", kEqualization, p.equalization);
  p.ransac = read_enum(m, "ransac", kRansac, p.ransac);

  auto positive = [&](const char* key, double v) {
    if (!(v > 0.0)) m.fail(key, "must be positive");
  };
  positive("num_features", p.num_features);
  positive("grid_cols", p.grid_cols);
  positive("grid_rows", p.grid_rows);
  positive("fast_threshold", p.fast_threshold);
  positive("lk_window", p.lk_window);
  positive("lk_max_iterations", p.lk_max_iterations);
  positive("lk_predicted_max_iterations", p.lk_predicted_max_iterations);
  positive("lk_predicted_epsilon", p.lk_predicted_epsilon);
  positive("ransac_threshold_px", p.ransac_threshold_px);
  if (p.lk_window % 2 == 0) m.fail("lk_window", "must be odd");
  if (p.template_half < 2 || p.template_half > 20) m.fail("template_half", "must be in [2, 20]");
  positive("template_iterations", p.template_iterations);
  if (p.lk_levels < 0 || p.lk_levels > 8) m.fail("lk_levels", "must be in [0, 8]");
  if (p.stereo_lk_levels < 0 || p.stereo_lk_levels > 8) {
    m.fail("stereo_lk_levels", "must be in [0, 8]");
  }
  if (p.stereo_track_lk_levels < 0 || p.stereo_track_lk_levels > 8) {
    m.fail("stereo_track_lk_levels", "must be in [0, 8]");
  }
  if (p.image_bit_depth != 0 && (p.image_bit_depth < 9 || p.image_bit_depth > 16)) {
    m.fail("image_bit_depth", "must be 0 (auto) or in [9, 16] (significant bits of 16-bit images)");
  }
  if (p.detect_min_missing < 1) m.fail("detect_min_missing", "must be >= 1");
  if (p.stereo_retry_frames < 0) m.fail("stereo_retry_frames", "must be >= 0");
  if (p.detect_cell_retry_frames < 0) m.fail("detect_cell_retry_frames", "must be >= 0");
  if (p.min_distance_px < 0.0) m.fail("min_distance_px", "must be >= 0");
  if (!(p.fast_noise_factor >= 0.0)) m.fail("fast_noise_factor", "must be >= 0");
  if (p.ransac_confidence <= 0.0 || p.ransac_confidence >= 1.0) {
    m.fail("ransac_confidence", "must be in (0, 1)");
  }
  m.check_unknown();
  return p;
}

FrontendParams load_frontend_params(const std::filesystem::path& path) {
  const io::YamlMap root = io::YamlMap::load_file(path);
  if (root.has("frontend")) {
    const io::YamlMap sub = root.get_map("frontend");
    const FrontendParams p = frontend_params_from_yaml(sub);
    root.check_unknown();
    return p;
  }
  return frontend_params_from_yaml(root);
}

std::string to_yaml(const FrontendParams& p) {
  std::ostringstream os;
  os << "equalization: " << enum_name(kEqualization, p.equalization) << "\n"
     << "ransac: " << enum_name(kRansac, p.ransac) << "\n";
  for (const auto& f : kInts) os << f.key << ": " << p.*f.member << "\n";
  for (const auto& f : kBools) os << f.key << ": " << (p.*f.member ? "true" : "false") << "\n";
  for (const auto& f : kDoubles) os << f.key << ": " << io::format_double(p.*f.member) << "\n";
  return os.str();
}

bool operator==(const FrontendParams& a, const FrontendParams& b) {
  if (a.equalization != b.equalization || a.ransac != b.ransac) return false;
  for (const auto& f : kInts) {
    if (a.*f.member != b.*f.member) return false;
  }
  for (const auto& f : kDoubles) {
    if (a.*f.member != b.*f.member) return false;
  }
  for (const auto& f : kBools) {
    if (a.*f.member != b.*f.member) return false;
  }
  return true;
}

}  // namespace vid
