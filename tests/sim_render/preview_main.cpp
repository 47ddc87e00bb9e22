// Renders a few views of a scenario's scene to PNG files (for looking at them).
// usage: sim_render_preview SCENARIO.yaml OUT_PREFIX
#include <Eigen/Geometry>
#include <chrono>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "sim/render/renderer.h"
#include "sim/render/scene.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: sim_render_preview SCENARIO.yaml OUT_PREFIX\n");
    return 2;
  }
  const vid::sim::Scene scene = vid::sim::scene_from_scenario_file(argv[1]);
  vid::CameraCalib calib;
  calib.intrinsics << 382.59014892578125, 382.59014892578125, 323.421142578125, 242.06617736816406;
  calib.distortion_coeffs << -0.05, 0.01, 0.0005, -0.0003;
  vid::sim::Renderer renderer(scene, calib, 2);
  const Eigen::Vector3d c = scene.config().room_center;
  // Optional: a view of the checkerboard from 1.5 m (as in the checkerboard preset).
  if (scene.checkerboard_surface() >= 0) {
    const auto& cb = scene.config().checkerboard;
    const int axis = scene.checkerboard_surface() / 2;
    const double sign = scene.checkerboard_surface() % 2 == 1 ? 1.0 : -1.0;
    Eigen::Vector3d board = Eigen::Vector3d::Zero();
    board[axis] = sign > 0 ? scene.room_max()[axis] : scene.room_min()[axis];
    board[axis == 0 ? 1 : 0] = cb.center.x();
    board.z() = cb.center.y();
    Eigen::Vector3d p = board;
    p[axis] -= sign * 1.5;
    const Eigen::Vector3d zc = (board - p).normalized();
    const Eigen::Vector3d xc = zc.cross(Eigen::Vector3d::UnitZ()).normalized();
    Eigen::Isometry3d T_WC = Eigen::Isometry3d::Identity();
    T_WC.linear() << xc, zc.cross(xc), zc;
    T_WC.translation() = p + Eigen::Vector3d(0.0, 0.1, 0.05);
    cv::imwrite(std::string(argv[2]) + "_board.png", renderer.render(T_WC));
  }
  for (int k = 0; k < 6; ++k) {
    // Camera looks along +z_C; yaw around the room centre, slightly downward.
    const double yaw = k * M_PI / 3.0;
    Eigen::Matrix3d R_WC;
    const Eigen::Vector3d z(std::cos(yaw), std::sin(yaw), -0.15);
    const Eigen::Vector3d zc = z.normalized();
    const Eigen::Vector3d xc = zc.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d yc = zc.cross(xc);
    R_WC << xc, yc, zc;
    Eigen::Isometry3d T_WC = Eigen::Isometry3d::Identity();
    T_WC.linear() = R_WC;
    T_WC.translation() = c + Eigen::Vector3d(0.3, -0.2, 0.0);
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat img = renderer.render(T_WC);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const std::string path = std::string(argv[2]) + "_" + std::to_string(k) + ".png";
    cv::imwrite(path, img);
    std::printf("%s  %.1f ms\n", path.c_str(), ms);
  }
  return 0;
}
