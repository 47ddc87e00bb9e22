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
  return c;
}

}  // namespace vid::sim
