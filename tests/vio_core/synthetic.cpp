// Synthetic data generator for the estimator tests (see synthetic.h).
#include "synthetic.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/so3.h"

namespace vid::test {
namespace {
using Eigen::Matrix3d;
using Eigen::Vector3d;

Vector3d pos(double t) {
  return Vector3d(1.5 * std::sin(0.6 * t), 1.2 * std::sin(0.8 * t + 0.5), 1.0 + 0.3 * std::sin(1.1 * t));
}
Vector3d acc(double t) {
  return Vector3d(-1.5 * 0.36 * std::sin(0.6 * t), -1.2 * 0.64 * std::sin(0.8 * t + 0.5),
                  -0.3 * 1.21 * std::sin(1.1 * t));
}
Vector3d vel(double t) {
  return Vector3d(1.5 * 0.6 * std::cos(0.6 * t), 1.2 * 0.8 * std::cos(0.8 * t + 0.5),
                  0.3 * 1.1 * std::cos(1.1 * t));
}
Vector3d force_W(const SynthConfig& c, double t) {
  return c.force_amplitude *
         Vector3d(0.8 * std::sin(0.3 * t) + 0.2, 0.6 * std::cos(0.25 * t), 0.3 * std::sin(0.4 * t));
}
double yaw(double t) { return 0.6 * std::sin(0.35 * t) + 0.1 * t; }

Matrix3d rotation(const SynthConfig& c, double t) {
  const Vector3d g(0, 0, -c.gravity);
  const Vector3d thrust_W = acc(t) - g - force_W(c, t);  // R T_m = a - g - f
  const Vector3d z = thrust_W.normalized();
  const Vector3d x_c(std::cos(yaw(t)), std::sin(yaw(t)), 0.0);
  const Vector3d y = z.cross(x_c).normalized();
  const Vector3d x = y.cross(z);
  Matrix3d R;
  R << x, y, z;
  return R;
}

Vector3d omega(const SynthConfig& c, double t) {
  const double h = 1e-5;
  const Matrix3d Rm = rotation(c, t - h), Rp = rotation(c, t + h);
  return so3::log(Rm.transpose() * Rp) / (2 * h);
}

}  // namespace

TruthState synth_truth(const SynthConfig& c, double t) {
  TruthState s;
  s.t_ns = static_cast<TimeNs>(std::llround(t * 1e9));
  s.p = pos(t);
  s.v = vel(t);
  const Matrix3d R = rotation(c, t);
  s.q = so3::normalized(Eigen::Quaterniond(R));
  s.F_W = force_W(c, t);
  s.F_I = R.transpose() * s.F_W;
  return s;
}

SynthData generate(const SynthConfig& c) {
  SynthData d;
  std::mt19937 rng(c.seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  const Vector3d g(0, 0, -c.gravity);
  const double k = 1e-5;  // N / unit^2 per rotor
  d.vehicle.mass_kg = c.mass;
  d.vehicle.gravity = c.gravity;
  d.vehicle.rotor_thrust_coefficients = {k, k, k, k};

  // Cameras: forward-looking (camera z = body x), optional stereo baseline 0.1 m along body -y.
  for (int i = 0; i < (c.stereo ? 2 : 1); ++i) {
    CameraCalib cam;
    cam.cam_id = i;
    cam.intrinsics = Eigen::Vector4d(c.focal, c.focal, 320, 240);
    cam.distortion = DistortionModel::kNone;
    Matrix3d R_IC;
    R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    cam.T_IC.linear() = R_IC;
    cam.T_IC.translation() = Vector3d(0.1, -0.1 * i, 0.05);
    d.cameras.push_back(cam);
  }
  // Landmarks on a shell around the flight volume.
  std::vector<Vector3d> lm;
  for (int i = 0; i < c.landmarks; ++i) {
    Vector3d u(nd(rng), nd(rng), 0.5 * nd(rng));
    u.normalize();
    const double r = 5.0 + 3.0 * (0.5 + 0.5 * std::tanh(nd(rng)));
    lm.push_back(u * r + Vector3d(0, 0, 1.0));
  }

  struct Item {
    TimeNs t;
    int order;
    Measurement m;
  };
  std::vector<Item> items;
  const double dt_imu = 1.0 / c.imu_rate;
  const int n_imu = static_cast<int>(std::floor(c.duration * c.imu_rate)) + 1;
  for (int i = 0; i < n_imu; ++i) {
    const double t = i * dt_imu;
    const TruthState s = synth_truth(c, t);
    d.truth.push_back(s);
    if (c.imu_gap.contains(t)) continue;
    ImuSample imu;
    imu.t_ns = s.t_ns;
    const Matrix3d R = s.q.toRotationMatrix();
    imu.gyro_I = omega(c, t) + c.b_g;
    imu.accel_I = R.transpose() * (acc(t) - g) + c.b_a;
    if (c.noisy) {
      const double sg = c.gyro_density * std::sqrt(c.imu_rate);
      const double sa = c.accel_density * std::sqrt(c.imu_rate);
      imu.gyro_I += sg * Vector3d(nd(rng), nd(rng), nd(rng));
      imu.accel_I += sa * Vector3d(nd(rng), nd(rng), nd(rng));
    }
    items.push_back({imu.t_ns, 1, imu});
  }
  const int n_rot = static_cast<int>(std::floor(c.duration * c.rotor_rate)) + 1;
  for (int i = 0; i < n_rot; ++i) {
    const double t = i / c.rotor_rate;
    if (c.rotor_gap.contains(t)) continue;
    const TruthState s = synth_truth(c, t);
    const Vector3d thrust_W = acc(t) - g - s.F_W;
    double Tm = thrust_W.norm();
    if (c.noisy) Tm += c.thrust_density * std::sqrt(c.rotor_rate) * nd(rng);
    RotorSample r;
    r.t_ns = s.t_ns;
    const double n = std::sqrt(Tm * c.mass / (4 * k));
    r.speeds = {n, n, n, n};
    items.push_back({r.t_ns, 0, r});
  }
  const int n_cam = static_cast<int>(std::floor(c.duration * c.cam_rate)) + 1;
  for (int i = 0; i < n_cam; ++i) {
    const double t = i / c.cam_rate;
    if (c.camera_gap.contains(t)) continue;
    const TruthState s = synth_truth(c, t);
    FeatureFrame f;
    f.t_ns = s.t_ns;
    const Matrix3d R_WI = s.q.toRotationMatrix();
    for (std::size_t j = 0; j < lm.size(); ++j) {
      for (const CameraCalib& cam : d.cameras) {
        const Matrix3d R_WC = R_WI * cam.T_IC.linear();
        const Vector3d p_WC = s.p + R_WI * cam.T_IC.translation();
        const Vector3d p_C = R_WC.transpose() * (lm[j] - p_WC);
        if (p_C.z() < 0.3) continue;
        Eigen::Vector2d xy = p_C.head<2>() / p_C.z();
        if (std::abs(xy.x()) > 0.75 || std::abs(xy.y()) > 0.55) continue;
        if (c.noisy) xy += (c.pixel_sigma / c.focal) * Eigen::Vector2d(nd(rng), nd(rng));
        FeatureObservation o;
        o.cam_id = cam.cam_id;
        o.feature_id = j;
        o.uv_norm = xy;
        o.uv = Eigen::Vector2d(c.focal * xy.x() + 320, c.focal * xy.y() + 240);
        o.has_norm = true;
        f.observations.push_back(o);
      }
    }
    items.push_back({f.t_ns, 2, f});
  }
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return a.t != b.t ? a.t < b.t : a.order < b.order;
  });
  for (Item& it : items) d.stream.push_back(std::move(it.m));
  return d;
}

EstimatorConfig matching_config(const SynthConfig& c, const SynthData& d, PropagationMode mode) {
  EstimatorConfig pc;
  EstimatorParams& p = pc.params;
  p.mode = mode;
  p.gravity = c.gravity;
  p.imu_rate_hz = c.imu_rate;
  // Small positive densities when the data is exact keep P well conditioned.
  p.gyro_noise_density = c.noisy ? c.gyro_density : 1e-5;
  p.accel_noise_density = c.noisy ? c.accel_density : 1e-4;
  p.thrust_noise_density = c.noisy ? c.thrust_density : 1e-4;
  p.gyro_random_walk = 1e-5;
  p.accel_random_walk = 1e-4;
  // The synthetic force is a slow body-frame-friendly signal; these tests keep the seed's
  // body-frame random-walk model (the world-frame / force-rate model is tested on the
  // simulator data and in test_propagation_jacobians / test_state).
  p.force_frame = ForceFrame::kBody;
  p.force_random_walk = 0.2;
  p.force_rate_random_walk = 0.0;
  p.pixel_noise_px = c.noisy ? c.pixel_sigma : 0.01;
  p.init_mode = InitMode::kGroundTruth;
  p.init_sigma_gyro_bias = 0.01;
  p.init_sigma_accel_bias = 0.1;
  p.init_sigma_force = 0.3;
  pc.vehicle = d.vehicle;
  pc.cameras = d.cameras;
  return pc;
}

ImuState initial_state(const SynthConfig& c) {
  const TruthState s = synth_truth(c, 0.0);
  ImuState x;
  x.T_WI = {s.q, s.p};
  x.v_WI = s.v;
  x.F_ext = s.F_I;
  return x;
}

}  // namespace vid::test
