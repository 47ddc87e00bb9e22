#include <yaml-cpp/yaml.h>

#include "sim/render/renderer.h"
#include "yaml_fields.h"

namespace vid::sim {

RenderConfig parse_render_config(const YAML::Node& node, const std::string& file) {
  RenderConfig c;
  const detail::YamlMap m(node, file, "render");
  m.allow_only({"supersampling", "noise_sigma", "brightness_amplitude", "brightness_period_s",
                "brightness_jitter", "seed"});
  m.read("supersampling", &c.supersampling);
  m.read("noise_sigma", &c.noise_sigma);
  m.read("brightness_amplitude", &c.brightness_amplitude);
  m.read("brightness_period_s", &c.brightness_period_s);
  m.read("brightness_jitter", &c.brightness_jitter);
  m.read("seed", &c.seed);
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
