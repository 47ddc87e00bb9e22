#include "vid_system/force_check.h"

#include <fmt/format.h>

namespace vid::system {

void add_force_check(nlohmann::json& s, const ForceMagnitude& f, double gravity) {
  if (!s.contains("warnings")) s["warnings"] = nlohmann::json::array();
  if (f.samples() == 0) return;
  const double mean = f.mean_mps2(), in_g = mean / gravity;
  s["force_check"] = {{"mean_norm_mps2", mean}, {"mean_norm_g", in_g}, {"estimates", f.samples()},
                      {"warn_above_g", kForceNear2gThreshold}};
  if (in_g <= kForceNear2gThreshold) return;
  // Thrust along +z of the IMU frame (z up) and an accelerometer reading -g at hover disagree
  // by 2 g; a real external force that large for a whole run is not plausible.
  s["warnings"].push_back(fmt::format(
      "external_force_near_2g: the estimated external force averages {:.1f} m/s^2 ({:.2f} g) over the run: the "
      "accelerometer sign or the IMU frame is probably flipped against the thrust, which acts along +z of the IMU "
      "frame (z up; at rest the accelerometer reads +{:.2f} m/s^2 on the up axis): check the signs of imu0/data.csv "
      "a_RS_S_x/y/z and the frame of imu0 (a z-down IMU needs its data converted)",
      mean, in_g, gravity));
}

}  // namespace vid::system
