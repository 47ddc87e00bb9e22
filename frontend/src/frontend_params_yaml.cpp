#include "frontend/frontend_params_yaml.h"

namespace vid {

FrontendParams frontend_params_from_yaml(const io::YamlMap& m, FrontendParams p) {
  p.num_features = m.get_int("num_features", p.num_features);
  p.grid_cols = m.get_int("grid_cols", p.grid_cols);
  p.grid_rows = m.get_int("grid_rows", p.grid_rows);
  p.fast_threshold = m.get_int("fast_threshold", p.fast_threshold);
  p.fast_threshold_min = m.get_int("fast_threshold_min", p.fast_threshold_min);
  p.min_distance_px = m.get_double("min_distance_px", p.min_distance_px);
  p.border_px = m.get_int("border_px", p.border_px);
  p.detect_min_missing = m.get_int("detect_min_missing", p.detect_min_missing);
  p.detect_cell_retry_frames = m.get_int("detect_cell_retry_frames", p.detect_cell_retry_frames);

  const std::string eq = m.get_string("equalization", "");
  if (eq == "none") p.equalization = Equalization::kNone;
  else if (eq == "histogram") p.equalization = Equalization::kHistogram;
  else if (eq == "clahe") p.equalization = Equalization::kClahe;
  else if (!eq.empty()) m.fail("equalization", "expected none|histogram|clahe, got '" + eq + "'");
  p.clahe_clip_limit = m.get_double("clahe_clip_limit", p.clahe_clip_limit);
  p.clahe_tile = m.get_int("clahe_tile", p.clahe_tile);

  p.lk_levels = m.get_int("lk_levels", p.lk_levels);
  p.lk_window = m.get_int("lk_window", p.lk_window);
  p.lk_max_iterations = m.get_int("lk_max_iterations", p.lk_max_iterations);
  p.lk_epsilon = m.get_double("lk_epsilon", p.lk_epsilon);
  p.lk_predicted_max_iterations =
      m.get_int("lk_predicted_max_iterations", p.lk_predicted_max_iterations);
  p.lk_predicted_epsilon = m.get_double("lk_predicted_epsilon", p.lk_predicted_epsilon);
  p.lk_min_eigen = m.get_double("lk_min_eigen", p.lk_min_eigen);
  p.fb_check_px = m.get_double("fb_check_px", p.fb_check_px);
  p.template_refinement = m.get_bool("template_refinement", p.template_refinement);
  p.template_half = m.get_int("template_half", p.template_half);
  p.template_iterations = m.get_int("template_iterations", p.template_iterations);
  p.template_epsilon_px = m.get_double("template_epsilon_px", p.template_epsilon_px);
  p.template_min_zncc = m.get_double("template_min_zncc", p.template_min_zncc);
  p.template_max_shift_px = m.get_double("template_max_shift_px", p.template_max_shift_px);

  const std::string rs = m.get_string("ransac", "");
  if (rs == "none") p.ransac = RansacMode::kNone;
  else if (rs == "fundamental") p.ransac = RansacMode::kFundamental;
  else if (rs == "two_point") p.ransac = RansacMode::kTwoPoint;
  else if (!rs.empty()) m.fail("ransac", "expected none|fundamental|two_point, got '" + rs + "'");
  p.ransac_threshold_px = m.get_double("ransac_threshold_px", p.ransac_threshold_px);
  p.ransac_confidence = m.get_double("ransac_confidence", p.ransac_confidence);
  p.ransac_max_iterations = m.get_int("ransac_max_iterations", p.ransac_max_iterations);

  p.stereo = m.get_bool("stereo", p.stereo);
  p.stereo_epipolar_px = m.get_double("stereo_epipolar_px", p.stereo_epipolar_px);
  p.stereo_lk_levels = m.get_int("stereo_lk_levels", p.stereo_lk_levels);
  p.stereo_track_lk_levels = m.get_int("stereo_track_lk_levels", p.stereo_track_lk_levels);
  p.stereo_fb_check_px = m.get_double("stereo_fb_check_px", p.stereo_fb_check_px);
  p.stereo_max_disparity_px = m.get_double("stereo_max_disparity_px", p.stereo_max_disparity_px);
  p.stereo_min_depth_m = m.get_double("stereo_min_depth_m", p.stereo_min_depth_m);
  p.gyro_prediction = m.get_bool("gyro_prediction", p.gyro_prediction);

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
  if (p.detect_min_missing < 1) m.fail("detect_min_missing", "must be >= 1");
  if (p.detect_cell_retry_frames < 0) m.fail("detect_cell_retry_frames", "must be >= 0");
  if (p.min_distance_px < 0.0) m.fail("min_distance_px", "must be >= 0");
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

}  // namespace vid
