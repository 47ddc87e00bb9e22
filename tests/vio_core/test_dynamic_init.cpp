// In-flight initialization math (vio_core/inertial_alignment.h, dynamic_initializer.h) on an
// analytic flight: exact data gives the exact state; with noise, the covariance it reports is
// the spread it has (NEES over Monte-Carlo draws).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/so3.h"
#include "vio_core/dynamic_initializer.h"
#include "vio_core/inertial_alignment.h"

namespace {
using namespace vid;
using Eigen::Matrix3d;
using Eigen::Vector3d;

const Vector3d kG(0, 0, -9.81);

// Flight: position and orientation analytic; returns R_WI, p, v, a (world).
struct Truth {
  Matrix3d R;
  Vector3d p, v, acc, w_I;
};
// cruise: the same rotations, but a straight line at constant velocity (no acceleration, so
// one camera cannot tell the scale).
Truth truth(double t, bool cruise = false) {
  Truth s;
  s.p = Vector3d(1.5 * std::sin(0.8 * t), 1.0 * std::cos(0.6 * t), 0.3 * std::sin(1.3 * t));
  s.v = Vector3d(1.2 * std::cos(0.8 * t), -0.6 * std::sin(0.6 * t), 0.39 * std::cos(1.3 * t));
  s.acc = Vector3d(-0.96 * std::sin(0.8 * t), -0.36 * std::cos(0.6 * t), -0.507 * std::sin(1.3 * t));
  const auto rot = [](double u) -> Matrix3d {
    return so3::exp(Vector3d(0.0, 0.0, 0.7 * u)) * so3::exp(Vector3d(0.15 * std::sin(1.1 * u), 0.1 * std::cos(0.9 * u), 0));
  };
  s.R = rot(t);
  const double h = 1e-5;
  s.w_I = so3::log(rot(t - h).transpose() * rot(t + h)) / (2 * h);
  if (cruise) {
    s.v = Vector3d(1.0, 0.3, 0.0);
    s.p = s.v * t;
    s.acc.setZero();
  }
  return s;
}

struct Scene {
  std::vector<CameraCalib> cams;
  std::vector<Vector3d> landmarks;
};
Scene scene(unsigned seed) {
  Scene sc;
  for (int c = 0; c < 2; ++c) {
    CameraCalib cam;
    cam.cam_id = c;
    cam.intrinsics = Eigen::Vector4d(400, 400, 320, 240);
    Matrix3d R_IC;  // camera looking along body x
    R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    cam.T_IC.linear() = R_IC;
    cam.T_IC.translation() = Vector3d(0.1, c == 0 ? 0.05 : -0.05, 0.0);
    sc.cams.push_back(cam);
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 3000; ++i) {  // a room: walls 6 m around
    const double az = M_PI * u(rng), z = 2.0 * u(rng);
    sc.landmarks.emplace_back(6.0 * std::cos(az), 6.0 * std::sin(az), z);
  }
  return sc;
}

struct Noise {
  double accel = 0.0, gyro = 0.0, pixel = 0.0;
  Vector3d b_a = Vector3d::Zero();
  Vector3d b_g = Vector3d::Zero();
  double gyro_garbage_s = 0.0;  // gyro samples in (t0, t0 + this] are N(0, 300) rad/s (a burst's end)
};

// One camera of the scene (the mono initializer).
Scene mono(Scene sc) {
  sc.cams.resize(1);
  return sc;
}

// Feeds `seconds` of IMU (400 Hz) and frames (20 Hz) starting at t0; returns the result (and
// with @p why the initializer's last rejection).
std::optional<InitResult> run(const EstimatorParams& p, const Scene& sc, double t0, const Noise& n, unsigned seed,
                              DynamicInitDiagnostics* diag = nullptr, double seconds = 1.2, bool cruise = false,
                              std::string* why = nullptr) {
  DynamicInitializer init(p, sc.cams);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  std::optional<InitResult> r;
  const int imu_per_frame = 20;
  for (int i = 0; i <= static_cast<int>(seconds * 400); ++i) {
    const double t = t0 + i / 400.0;
    const Truth s = truth(t, cruise);
    Vector3d a = s.R.transpose() * (s.acc - kG) + n.b_a, w = s.w_I + n.b_g;
    for (int k = 0; k < 3; ++k) {
      a[k] += n.accel * std::sqrt(400.0) * n01(rng);
      w[k] += n.gyro * std::sqrt(400.0) * n01(rng);
    }
    if (i > 0 && t - t0 <= n.gyro_garbage_s) w = 300.0 * Vector3d(n01(rng), n01(rng), n01(rng));
    const TimeNs tn = static_cast<TimeNs>(std::llround(t * 1e9));
    init.add_imu(tn, w, a, Vector3d(0, 0, 9.81));
    if (i % imu_per_frame != 0) continue;
    FeatureFrame f;
    f.t_ns = tn;
    for (std::size_t j = 0; j < sc.landmarks.size(); ++j) {
      for (const CameraCalib& c : sc.cams) {
        const Vector3d X_I = s.R.transpose() * (sc.landmarks[j] - s.p);
        const Vector3d X_C = c.T_IC.inverse() * X_I;
        if (X_C.z() < 0.5) continue;
        Eigen::Vector2d xy = X_C.head<2>() / X_C.z();
        if (std::abs(xy.x()) > 0.8 || std::abs(xy.y()) > 0.6) continue;
        xy += n.pixel / 400.0 * Eigen::Vector2d(n01(rng), n01(rng));
        FeatureObservation o;
        o.cam_id = c.cam_id;
        o.feature_id = j;
        o.uv_norm = xy;
        o.has_norm = true;
        f.observations.push_back(o);
      }
    }
    if (auto res = init.add_frame(f); res && !r) {
      r = res;
      if (diag) *diag = init.diagnostics();
    }
  }
  if (why) *why = init.last_rejection();
  return r;
}

EstimatorParams params(double accel_density, double pixel) {
  EstimatorParams p;
  p.accel_noise_density = std::max(accel_density, 1e-4);
  p.pixel_noise_px = std::max(pixel, 1e-3);
  p.mode = PropagationMode::kImu;
  p.init_dynamic_window_s = 1.0;
  return p;
}

// Error (true - estimate) of (theta tilt, v_W) in the estimate's yaw-free world: the estimate
// has yaw 0, so the truth is rotated by the yaw between them first.
Eigen::Matrix<double, 6, 1> error(const InitResult& r, double t, bool cruise = false) {
  const Truth s = truth(t, cruise);
  const Matrix3d R_est = r.x.T_WI.q.toRotationMatrix();
  // world alignment: rotation about z taking the true body x heading to the estimate's (the
  // estimate's gauge: yaw 0 is body x projected on the horizontal)
  const double yaw = std::atan2(R_est(1, 0), R_est(0, 0)) - std::atan2(s.R(1, 0), s.R(0, 0));
  const Matrix3d Rz = so3::exp(Vector3d(0, 0, yaw));
  const Matrix3d R_true = Rz * s.R;
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = so3::log(R_est.transpose() * R_true);
  e.tail<3>() = Rz * s.v - r.x.v_WI;
  return e;
}

// NEES per dof of (tilt, velocity) at init against the covariance handed to the filter.
Eigen::Vector2d nees_per_dof(const InitResult& r, bool cruise = false) {
  const Eigen::Matrix<double, 6, 1> e = error(r, r.t_ns * 1e-9, cruise);
  Eigen::Matrix<double, 6, 6> P;
  P << r.P.block<3, 3>(0, 0), r.P.block<3, 3>(0, 6), r.P.block<3, 3>(6, 0), r.P.block<3, 3>(6, 6);
  // tilt: drop the yaw direction (the gauge, sigma 1e-4 against the aligned yaw)
  const Vector3d z_I = r.x.T_WI.q.conjugate() * Vector3d::UnitZ();
  Eigen::Matrix<double, 2, 3> Bt;
  Bt.row(0) = z_I.unitOrthogonal().transpose();
  Bt.row(1) = z_I.cross(z_I.unitOrthogonal()).transpose();
  const Eigen::Vector2d et = Bt * e.head<3>();
  return {et.dot((Bt * P.topLeftCorner<3, 3>() * Bt.transpose()).ldlt().solve(et)) / 2.0,
          e.tail<3>().dot(P.bottomRightCorner<3, 3>().ldlt().solve(e.tail<3>())) / 3.0};
}

// Mean NEES per dof of (tilt, velocity) over Monte-Carlo draws, expected in [0.5, 1.5] (the
// mean of 40-60 chi2 draws per dof is 1 +- ~0.2 at 2 sigma).
struct MeanNees {
  double tilt = 0.0, v = 0.0;
  int runs = 0;
  void add(const Eigen::Vector2d& nees) {
    tilt += nees[0];
    v += nees[1];
    ++runs;
  }
  void expect_consistent(const char* what) const {
    std::printf("%s NEES per dof over %d draws: tilt %.2f, velocity %.2f\n", what, runs, tilt / runs, v / runs);
    EXPECT_GT(tilt / runs, 0.5);
    EXPECT_LT(tilt / runs, 1.5);
    EXPECT_GT(v / runs, 0.5);
    EXPECT_LT(v / runs, 1.5);
  }
};

TEST(InertialAlignment, AlphaCovarianceMatchesAnIntegral) {
  // int_{max}^0 (u - a)(u - b) du by the midpoint rule
  const double a = -0.8, b = -0.3;
  double sum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double u = b + (0.0 - b) * (i + 0.5) / n;
    sum += (u - a) * (u - b) * (0.0 - b) / n;
  }
  EXPECT_NEAR(align::alpha_covariance(a, b), sum, 1e-9);
  EXPECT_NEAR(align::alpha_covariance(b, a), sum, 1e-9);
}

TEST(DynamicInit, ExactDataGivesTheExactState) {
  const Scene sc = scene(1);
  const EstimatorParams p = params(0.0, 0.0);
  DynamicInitDiagnostics d;
  Noise exact;
  exact.b_g = Vector3d(0.02, -0.08, 0.05);  // EuRoC's IMU has 0.077 rad/s on one axis
  const auto r = run(p, sc, 2.0, exact, 1, &d);
  ASSERT_TRUE(r.has_value());
  const double t = r->t_ns * 1e-9;
  EXPECT_NEAR(t, 3.0, 1e-6);
  const auto e = error(*r, t);
  EXPECT_LT(e.head<3>().norm(), 2e-4) << e.transpose();  // tilt
  EXPECT_LT(e.tail<3>().norm(), 2e-3) << e.transpose();  // velocity of ~1.4 m/s
  EXPECT_LT(r->x.b_a.norm(), 5e-3);
  EXPECT_LT((r->x.b_g - exact.b_g).norm(), 1e-4) << r->x.b_g.transpose();
  EXPECT_GE(d.landmarks, 15);
}

TEST(DynamicInit, GarbageGyroSamplesInTheWindowAreRefused) {
  // The first 40 ms of the first window are the end of a burst of garbage (vid_live's forced
  // divergence, tests/python/test_live_reinit.py): the gyro-bias solve would absorb them
  // (|b_g| 0.7 rad/s, visual chi2/dof 5e3) and hand over a state metres off after a second. The
  // window is refused; the next one, which starts after the burst, gives the exact state.
  const Scene sc = scene(1);
  const EstimatorParams p = params(0.0, 0.0);
  Noise n;
  n.gyro_garbage_s = 0.04;
  const auto r = run(p, sc, 2.0, n, 1);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->t_ns * 1e-9, 3.05, 1e-6);  // the window [2.05, 3.05] s, not [2.0, 3.0] s
  const auto e = error(*r, r->t_ns * 1e-9);
  EXPECT_LT(e.head<3>().norm(), 2e-4) << e.transpose();
  EXPECT_LT(r->x.b_g.norm(), 1e-4) << r->x.b_g.transpose();
}

TEST(DynamicInit, NeesOfTiltAndVelocityOverMonteCarloDraws) {
  // The simulator presets' noise: accelerometer 0.1 m/s^2/sqrt(Hz), 0.5 px, an accelerometer
  // bias drawn from its prior (0.1 m/s^2). Tilt (2 dof) and velocity (3 dof) NEES against the
  // reported covariance, averaged over draws: 1 per dof when the covariance is the spread.
  const Scene sc = scene(2);
  const EstimatorParams p = params(0.1, 0.5);
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  MeanNees nees;
  for (int i = 0; i < 60; ++i) {
    Noise n{0.1, 1e-4, 0.5, 0.1 * Vector3d(n01(rng), n01(rng), n01(rng)), 0.05 * Vector3d(n01(rng), n01(rng), n01(rng))};
    const double t0 = 0.5 + 0.37 * i;
    const auto r = run(p, sc, t0, n, 100 + i);
    ASSERT_TRUE(r.has_value()) << "draw " << i;
    nees.add(nees_per_dof(*r));
  }
  nees.expect_consistent("stereo");  // measured: tilt 0.94, velocity 0.83
}

TEST(DynamicInit, StereoScaleIsUnbiasedAtLowDisparity) {
  // Walls 6 m away, 10 cm baseline: 6.7 px of disparity, 0.5 px of noise, a near-ideal IMU.
  // The velocity at init is the stereo positions' scale times the true one; the linear solve
  // alone read it 0.966x here (rope_snap: 0.85-0.94x); with the reprojection refinement 0.995x.
  const Scene sc = scene(3);
  const EstimatorParams p = params(1e-3, 0.5);
  double scale = 0.0;
  int runs = 0;
  for (int i = 0; i < 20; ++i) {
    const double t0 = 0.5 + 0.53 * i;
    const auto r = run(p, sc, t0, Noise{1e-3, 1e-5, 0.5}, 300 + i);
    ASSERT_TRUE(r.has_value()) << "draw " << i;
    const Eigen::Matrix<double, 6, 1> e = error(*r, r->t_ns * 1e-9);
    const Vector3d v_est = r->x.v_WI, v_true = v_est + e.tail<3>();
    scale += v_est.dot(v_true) / v_true.squaredNorm();
    ++runs;
  }
  scale /= runs;
  std::printf("velocity scale at init over %d draws: %.4f\n", runs, scale);
  EXPECT_NEAR(scale, 1.0, 0.02);
}

EstimatorParams mono_params(double accel_density, double pixel) {
  EstimatorParams p = params(accel_density, pixel);
  p.init_dynamic_window_mono_s = 2.0;
  return p;
}

TEST(DynamicInit, MonoExactDataGivesTheExactState) {
  // One camera: the scale from the accelerometer (the flight accelerates by ~1 m/s^2).
  const Scene sc = mono(scene(1));
  const EstimatorParams p = mono_params(0.0, 0.0);
  DynamicInitDiagnostics d;
  Noise exact;
  exact.b_g = Vector3d(0.02, -0.08, 0.05);
  const auto r = run(p, sc, 2.0, exact, 1, &d, 2.2);
  ASSERT_TRUE(r.has_value());
  const double t = r->t_ns * 1e-9;
  EXPECT_NEAR(t, 4.0, 1e-6);
  const auto e = error(*r, t);
  EXPECT_LT(e.head<3>().norm(), 2e-4) << e.transpose();
  EXPECT_LT(e.tail<3>().norm(), 2e-3) << e.transpose();
  EXPECT_LT(r->x.b_a.norm(), 5e-3);
  EXPECT_LT((r->x.b_g - exact.b_g).norm(), 1e-4) << r->x.b_g.transpose();
  EXPECT_GE(d.landmarks, 15);
  // The window's poses: every frame but the last (which is the state's), in the new world.
  ASSERT_FALSE(r->window_poses.empty());
  EXPECT_LT(r->window_poses.back().t_ns, r->t_ns);
}

TEST(DynamicInit, MonoWithoutAccelerationIsRefused) {
  // Straight at constant velocity: any scale fits the bearings and the accelerometer alike, so
  // a mono window must be refused (with stereo the same flight initializes).
  const Scene sc = scene(1);
  std::string why;
  DynamicInitDiagnostics d;
  const auto r_mono = run(mono_params(0.1, 0.5), mono(sc), 2.0, Noise{0.1, 1e-4, 0.5}, 5, &d, 2.2, true, &why);
  std::printf("cruise scale sigma %.3f, v %.3f\n", d.scale_sigma, r_mono ? r_mono->x.v_WI.norm() : -1.0);
  EXPECT_FALSE(r_mono.has_value());
  EXPECT_FALSE(why.empty());
  std::printf("mono, no acceleration: %s\n", why.c_str());
  const auto r_stereo = run(params(0.1, 0.5), sc, 2.0, Noise{0.1, 1e-4, 0.5}, 5, nullptr, 1.2, true);
  ASSERT_TRUE(r_stereo.has_value());
  EXPECT_LT(error(*r_stereo, r_stereo->t_ns * 1e-9, true).tail<3>().norm(), 0.1);
}

TEST(DynamicInit, MonoNeesOfTiltAndVelocityOverMonteCarloDraws) {
  // As the stereo test above, one camera and a 2 s window.
  const Scene sc = mono(scene(2));
  const EstimatorParams p = mono_params(0.1, 0.5);
  std::mt19937 rng(8);
  std::normal_distribution<double> n01;
  MeanNees mean;
  for (int i = 0; i < 40; ++i) {
    Noise n{0.1, 1e-4, 0.5, 0.1 * Vector3d(n01(rng), n01(rng), n01(rng)), 0.05 * Vector3d(n01(rng), n01(rng), n01(rng))};
    std::string why;
    DynamicInitDiagnostics d;
    const auto r = run(p, sc, 0.5 + 0.37 * i, n, 200 + i, &d, 2.2, false, &why);
    if (!r) { std::printf("draw %d refused: %s\n", i, why.c_str()); continue; }
    const Eigen::Vector2d nees = nees_per_dof(*r);
    const Truth s = truth(r->t_ns * 1e-9);
    if (nees.maxCoeff() > 4.0)  // the draws that make the mean: which, how far off, how sure
      std::printf("draw %d: NEES/dof tilt %.2f velocity %.2f, velocity error %.3f m/s at sigma %.3f, |v| %.2f, scale "
                  "sigma %.3f, scale error %.3f\n",
                  i, nees[0], nees[1], error(*r, r->t_ns * 1e-9).tail<3>().norm(),
                  std::sqrt(r->P.block<3, 3>(6, 6).diagonal().maxCoeff()), s.v.norm(), d.scale_sigma,
                  r->x.v_WI.norm() / s.v.norm() - 1.0);
    mean.add(nees);
  }
  mean.expect_consistent("mono");  // measured: tilt 1.07, velocity 1.08
  // Ratchet at today's 36 of 40 within 0.2 s of retries (the 4 others: the up-to-scale start
  // not determined); the issue asks 95 % of starts within 3 s.
  EXPECT_GE(mean.runs, 36);
}

// The refinement's normal equations against numeric derivatives of its cost: the gradient
// 2 J^T r at a perturbed x (residuals of every size), and the Gauss-Newton matrix J^T J against
// half the cost's Hessian where the residuals vanish (there the two are equal); the gyro-bias
// block at d_bg = 0, where its first-order Jacobian is exact.
TEST(InertialAlignment, ReprojectionNormalEquationsMatchNumericDerivatives) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int K = 3, landmarks = 6;
  std::vector<Eigen::Matrix3d> R_Kk, J_bg;
  for (int k = 0; k <= K; ++k) {
    R_Kk.push_back(so3::exp(Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng))));
    J_bg.push_back(0.05 * (k - K) * Eigen::Matrix3d::Identity() + 0.01 * Eigen::Matrix3d::Random());
  }
  std::vector<Eigen::Isometry3d> T_IC(2, Eigen::Isometry3d::Identity());
  T_IC[1].translation() = Eigen::Vector3d(0.1, 0.0, 0.0);
  std::vector<Eigen::Vector3d> p(K), L(landmarks);
  for (Eigen::Vector3d& v : p) v = 0.2 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  for (Eigen::Vector3d& v : L) v = Eigen::Vector3d(u(rng), u(rng), 4.0 + u(rng));
  std::vector<align::Track> tracks(landmarks);
  std::vector<std::vector<bool>> keep(landmarks);
  for (int j = 0; j < landmarks; ++j) {
    for (int k = 0; k <= K; ++k) {
      for (int c = 0; c < 2; ++c) {
        const Eigen::Vector3d p_k = k < K ? p[k] : Eigen::Vector3d::Zero();
        const Eigen::Vector3d X_C = T_IC[c].inverse() * Eigen::Vector3d(R_Kk[k].transpose() * (L[j] - p_k));
        tracks[j].obs.push_back({k, c, X_C.head<2>() / X_C.z()});
        keep[j].push_back(true);
      }
    }
  }
  Eigen::VectorXd x_true(3 * K + 3 * landmarks + 3);
  for (int k = 0; k < K; ++k) x_true.segment<3>(3 * k) = p[k];
  for (int j = 0; j < landmarks; ++j) x_true.segment<3>(3 * K + 3 * j) = L[j];
  x_true.tail<3>().setZero();
  const double sigma = 0.002;
  const auto cost = [&](const Eigen::VectorXd& x) {
    return align::detail::reprojection_system(tracks, R_Kk, T_IC, sigma, J_bg, keep, x, nullptr, nullptr);
  };
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  // Gradient at a perturbed point (bias block held at 0).
  Eigen::VectorXd x = x_true;
  for (int i = 0; i < 3 * K + 3 * landmarks; ++i) x(i) += 0.02 * u(rng);
  align::detail::reprojection_system(tracks, R_Kk, T_IC, sigma, J_bg, keep, x, &H, &g);
  const double h = 1e-6;
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    const double numeric = (cost(xp) - cost(xm)) / (2.0 * h);
    EXPECT_NEAR(2.0 * g(i), numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << "gradient, component " << i;
  }
  // Gauss-Newton matrix at the exact solution: the cost's Hessian is 2 J^T J there.
  align::detail::reprojection_system(tracks, R_Kk, T_IC, sigma, J_bg, keep, x_true, &H, &g);
  EXPECT_LT(g.norm(), 1e-6);
  const double e = 1e-4;
  for (int i = 0; i < x_true.size(); ++i) {
    for (int j = i; j < x_true.size(); j += 5) {  // every 5th column: the same code path per block
      Eigen::VectorXd xpp = x_true, xpm = x_true, xmp = x_true, xmm = x_true;
      xpp(i) += e, xpp(j) += e;
      xpm(i) += e, xpm(j) -= e;
      xmp(i) -= e, xmp(j) += e;
      xmm(i) -= e, xmm(j) -= e;
      const double hess = (cost(xpp) - cost(xpm) - cost(xmp) + cost(xmm)) / (4.0 * e * e);
      EXPECT_NEAR(H(i, j), 0.5 * hess, 1e-4 * std::max(1.0, std::abs(H(i, j)))) << "H(" << i << ", " << j << ")";
    }
  }
}

}  // namespace
