/// @file test_consistency.cpp
/// @brief Physical consistency of every preset with noise off:
///  * m a_W = R_WI sum_i T_i z + F_ext_W + m g_W (T_i = k_i n_i^2 from the WRITTEN rotor speeds,
///    F_ext from force0, m from mass0) to 1e-6 relative at ground-truth samples;
///  * accelerometer - b_a = R_WI^T (a_W - g_W), gyroscope - b_g = body rate;
///  * integrating the IMU samples (RK4) from the true state reproduces ground-truth position
///    within 1 mm after 10 s (every 10 s window of the run).

#include <gtest/gtest.h>

#include <map>

#include "dynamics/rk4.h"
#include "sim_test_util.h"

namespace vid::sim::test {
namespace {

struct NavState {
  Eigen::Quaterniond q;
  Eigen::Vector3d v, p;
};

/// Derivative of a NavState (q as four plain coefficients w, x, y, z).
struct NavDot {
  Eigen::Vector4d dq;
  Eigen::Vector3d dv, dp;
};
NavDot operator+(const NavDot& a, const NavDot& b) { return {a.dq + b.dq, a.dv + b.dv, a.dp + b.dp}; }
NavDot operator*(double k, const NavDot& d) { return {k * d.dq, k * d.dv, k * d.dp}; }

/// @brief RK4 (dynamics/rk4.h) strapdown integration with inputs linearly interpolated between samples.
NavState integrate(NavState x, const ImuSample& a, const ImuSample& b, const Eigen::Vector3d& bg,
                   const Eigen::Vector3d& ba, const Eigen::Vector3d& g_W) {
  const double h = static_cast<double>(b.t_ns - a.t_ns) * 1e-9;
  auto f = [&](double t, const NavState& s) {
    const double alpha = t / h;  // 0, 1/2, 1: exact
    const Eigen::Vector3d w = (1 - alpha) * a.gyro_I + alpha * b.gyro_I - bg;
    const Eigen::Vector3d acc = (1 - alpha) * a.accel_I + alpha * b.accel_I - ba;
    const Eigen::Quaterniond qn = s.q.normalized();
    const Eigen::Quaterniond qd = s.q * Eigen::Quaterniond(0, w.x(), w.y(), w.z());
    return NavDot{0.5 * Eigen::Vector4d(qd.w(), qd.x(), qd.y(), qd.z()), qn * acc + g_W, s.v};
  };
  auto add = [](const NavState& s, const NavDot& d, double k) {
    NavState o;
    o.q = Eigen::Quaterniond(s.q.w() + k * d.dq[0], s.q.x() + k * d.dq[1], s.q.y() + k * d.dq[2], s.q.z() + k * d.dq[3]);
    o.v = s.v + k * d.dv;
    o.p = s.p + k * d.dp;
    return o;
  };
  x = dynamics::rk4_step<NavDot>(0.0, h, x, f, add);
  x.q.normalize();
  return x;
}

void check_preset(const std::string& name) {
  SCOPED_TRACE(name);
  Scenario sc = load_scenario(preset_path(name));
  sc.noise = false;
  sc.duration_s = std::min(sc.duration_s, 60.0);
  sc.trajectory.duration_s = sc.duration_s;
  sc.rotor.enabled = true;  // presets without a rotor stream (euroc_like) are checked with one
  Simulator sim(sc);
  Recording rec;
  sim.run(rec);
  ASSERT_GT(rec.gt.size(), 200u);
  const Eigen::Vector3d g_W(0, 0, -sc.vehicle.gravity);

  std::map<TimeNs, const RotorSample*> rotor_at;
  for (const auto& r : rec.rotor) rotor_at[r.t_ns] = &r;
  std::map<TimeNs, std::size_t> imu_at;
  for (std::size_t i = 0; i < rec.imu.size(); ++i) imu_at[rec.imu[i].t_ns] = i;

  ASSERT_EQ(rec.truth.size(), rec.gt.size());
  ASSERT_EQ(rec.force.size(), rec.gt.size());
  ASSERT_EQ(rec.mass.size(), rec.gt.size());
  std::size_t checked = 0;
  double worst_rel = 0.0, worst_acc = 0.0, worst_gyro = 0.0;
  for (std::size_t i = 0; i < rec.gt.size(); ++i) {
    const GroundTruthSample& gt = rec.gt[i];
    const TruthSample& tr = rec.truth[i];
    ASSERT_EQ(tr.t_ns, gt.t_ns);
    const Eigen::Matrix3d R = gt.T_WI.q.toRotationMatrix();
    const Eigen::Vector3d a_W = tr.forces.accel_W;
    // IMU at the same time: specific force and body rate.
    const auto it = imu_at.find(gt.t_ns);
    ASSERT_NE(it, imu_at.end()) << "no IMU sample at a ground-truth time";
    const ImuSample& imu = rec.imu[it->second];
    worst_acc = std::max(worst_acc, ((imu.accel_I - gt.b_a) - R.transpose() * (a_W - g_W)).norm());
    worst_gyro = std::max(worst_gyro, ((imu.gyro_I - gt.b_g) - tr.state.w_I).norm());
    // Newton with the written rotor speeds, force0 and mass0.
    const auto rit = rotor_at.find(gt.t_ns);
    if (rit == rotor_at.end()) continue;
    double thrust = 0.0;
    for (std::size_t k = 0; k < rit->second->speeds.size(); ++k) {
      const double n = rit->second->speeds[k];
      thrust += sc.vehicle.rotors[k].thrust_coeff * n * n;
    }
    const double m = rec.mass[i].mass_kg;
    const Eigen::Vector3d lhs = m * a_W;
    const Eigen::Vector3d rhs = R * Eigen::Vector3d(0, 0, thrust) + rec.force[i].f_W_N + m * g_W;
    const double scale = thrust + rec.force[i].f_W_N.norm() + m * sc.vehicle.gravity;
    worst_rel = std::max(worst_rel, (lhs - rhs).norm() / scale);
    ++checked;
  }
  EXPECT_GE(checked, rec.rotor.size() * 9 / 10) << "rotor samples must coincide with ground truth";
  EXPECT_LT(worst_rel, 1e-6);
  EXPECT_LT(worst_acc, 1e-9);
  EXPECT_LT(worst_gyro, 1e-12);

  // Strapdown integration over consecutive 10 s windows.
  const TimeNs window = 10'000'000'000LL;
  double worst_pos = 0.0;
  int windows = 0;
  for (std::size_t g0 = 0; g0 < rec.gt.size(); ++g0) {
    if ((rec.gt[g0].t_ns - rec.gt[0].t_ns) % window != 0) continue;
    const TimeNs t_end = rec.gt[g0].t_ns + window;
    if (t_end > rec.gt.back().t_ns) break;
    NavState x{rec.gt[g0].T_WI.q, rec.gt[g0].v_WI, rec.gt[g0].T_WI.p};
    std::size_t k = imu_at.at(rec.gt[g0].t_ns);
    std::size_t gi = g0;
    while (rec.imu[k].t_ns < t_end) {
      while (rec.gt[gi].t_ns < rec.imu[k].t_ns) ++gi;
      // Biases are constant with noise off; use the ground-truth values.
      x = integrate(x, rec.imu[k], rec.imu[k + 1], rec.gt[gi].b_g, rec.gt[gi].b_a, g_W);
      ++k;
    }
    const auto end_gt = std::find_if(rec.gt.begin(), rec.gt.end(), [&](const auto& s) { return s.t_ns == t_end; });
    ASSERT_NE(end_gt, rec.gt.end());
    worst_pos = std::max(worst_pos, (x.p - end_gt->T_WI.p).norm());
    ++windows;
  }
  EXPECT_GE(windows, 1);
  EXPECT_LT(worst_pos, 1e-3) << "IMU integration drifts from ground truth";
  std::printf("[%s] newton rel %.2e, accel %.2e, gyro %.2e, imu-integration %.3e m over %d windows\n",
              name.c_str(), worst_rel, worst_acc, worst_gyro, worst_pos, windows);
}

TEST(SimConsistency, Vid17Like) { check_preset("vid17_like"); }
TEST(SimConsistency, Vid18Like) { check_preset("vid18_like"); }
TEST(SimConsistency, VidLoaded) { check_preset("vid_loaded"); }
TEST(SimConsistency, EurocLike) { check_preset("euroc_like"); }
TEST(SimConsistency, Hover) { check_preset("hover"); }
TEST(SimConsistency, Checkerboard) { check_preset("checkerboard"); }
TEST(SimConsistency, FastYaw) { check_preset("fast_yaw"); }
TEST(SimConsistency, WindAndPushes) { check_preset("wind_gusts"); }
TEST(SimConsistency, MassLoss) { check_preset("spraying"); }

}  // namespace
}  // namespace vid::sim::test
