#include <yaml-cpp/yaml.h>

#include "sim/render/renderer.h"
#include "io/strict_yaml.h"

namespace vid::sim {

RenderConfig parse_render_config(const YAML::Node& node, const std::string& file) {
  RenderConfig c;
  const io::YamlMap m = io::YamlMap::from_node(node, file, "render");
  c.supersampling = m.get_int("supersampling", c.supersampling);
  c.noise_sigma = m.get_double("noise_sigma", c.noise_sigma);
  c.brightness_amplitude = m.get_double("brightness_amplitude", c.brightness_amplitude);
  c.brightness_period_s = m.get_double("brightness_period_s", c.brightness_period_s);
  c.brightness_jitter = m.get_double("brightness_jitter", c.brightness_jitter);
  c.seed = m.get_u64("seed", c.seed);
  c.exposure_s = m.get_double("exposure_s", c.exposure_s);
  c.exposure_samples = m.get_int("exposure_samples", c.exposure_samples);
  c.line_delay_s = m.get_double("line_delay_s", c.line_delay_s);
  c.vignetting = m.get_double("vignetting", c.vignetting);
  c.electrons_per_level = m.get_double("electrons_per_level", c.electrons_per_level);
  c.illumination = m.get_double("illumination", c.illumination);
  c.flicker_amplitude = m.get_double("flicker_amplitude", c.flicker_amplitude);
  c.flicker_hz = m.get_double("flicker_hz", c.flicker_hz);
  if (m.has("auto_exposure")) {
    const io::YamlMap a = m.get_map("auto_exposure");
    AutoExposureConfig& ae = c.auto_exposure;
    ae.enabled = true;
    ae.target_level = a.get_double("target_level", ae.target_level);
    ae.min_exposure_s = a.get_double("min_exposure_s", ae.min_exposure_s);
    ae.max_exposure_s = a.get_double("max_exposure_s", ae.max_exposure_s);
    ae.max_gain = a.get_double("max_gain", ae.max_gain);
    ae.rate = a.get_double("rate", ae.rate);
    a.check_unknown();
    if (ae.target_level < 10.0 || ae.target_level > 245.0) a.fail("target_level", "must be in [10, 245]");
    if (ae.min_exposure_s <= 0.0) a.fail("min_exposure_s", "must be > 0");
    if (ae.max_exposure_s < ae.min_exposure_s) a.fail("max_exposure_s", "must be >= min_exposure_s");
    if (ae.max_gain < 1.0 || ae.max_gain > 64.0) a.fail("max_gain", "must be in [1, 64]");
    if (ae.rate <= 0.0 || ae.rate > 1.0) a.fail("rate", "must be in (0, 1]");
  }
  m.accept("auto_exposure");  // read above when present
  m.check_unknown();
  if (c.supersampling < 1 || c.supersampling > 4) m.fail("supersampling", "must be in 1..4");
  if (c.noise_sigma < 0.0) m.fail("noise_sigma", "must be >= 0");
  if (c.brightness_amplitude < 0.0 || c.brightness_amplitude > 0.9) {
    m.fail("brightness_amplitude", "must be in [0, 0.9]");
  }
  if (c.brightness_period_s <= 0.0) m.fail("brightness_period_s", "must be > 0");
  if (c.brightness_jitter < 0.0 || c.brightness_jitter > 0.5) {
    m.fail("brightness_jitter", "must be in [0, 0.5]");
  }
  if (!(c.exposure_s >= 0.0) || c.exposure_s > 0.2) m.fail("exposure_s", "must be in [0, 0.2] s");
  if (c.exposure_samples < 1 || c.exposure_samples > 64) m.fail("exposure_samples", "must be in 1..64");
  if (!(c.line_delay_s >= 0.0) || c.line_delay_s > 1e-3) m.fail("line_delay_s", "must be in [0, 1e-3] s");
  if (!(c.vignetting >= 0.0) || c.vignetting > 0.9) m.fail("vignetting", "must be in [0, 0.9]");
  if (!(c.electrons_per_level >= 0.0)) m.fail("electrons_per_level", "must be >= 0 (0 = no shot noise)");
  if (!(c.illumination > 0.0) || c.illumination > 10.0) m.fail("illumination", "must be in (0, 10]");
  if (!(c.flicker_amplitude >= 0.0) || c.flicker_amplitude > 0.9) {
    m.fail("flicker_amplitude", "must be in [0, 0.9]");
  }
  if (!(c.flicker_hz > 0.0)) m.fail("flicker_hz", "must be > 0");
  if (c.auto_exposure.enabled && c.exposure_s <= 0.0) {
    m.fail("exposure_s", "auto_exposure needs the reference exposure exposure_s > 0");
  }
  return c;
}

}  // namespace vid::sim
