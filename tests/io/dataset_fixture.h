#pragma once
/// @file dataset_fixture.h
/// @brief Deterministic synthetic sequences (mono, stereo, feature-level) written with
/// DatasetWriter, and the measurements a reader must return for them.

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "io/dataset_writer.h"
#include "types/calibration.h"
#include "types/measurements.h"

namespace vid::io::test {

enum class SeqKind { kMono, kStereo, kFeatures };

/// @brief What was written, in the reader's documented merge order.
struct WrittenSequence {
  std::vector<Measurement> expected;
  std::vector<CameraCalib> cameras;
  ImuNoise imu;
  RotorSensor rotor;
  VehicleParams vehicle;
};

/// @brief Tie-break rank of a measurement at equal timestamps (DatasetReader's contract).
inline int merge_rank(const Measurement& m) {
  static const int kRank[] = {0 /*Imu*/, 1 /*Rotor*/, 2 /*Thrust*/, 3 /*Image*/, 4 /*Feature*/,
                              5 /*Force*/, 6 /*Mass*/, 7 /*GT*/};
  return kRank[m.index()];
}

/// @brief Write a 0.5 s sequence of every stream with full-precision random values.
inline WrittenSequence write_sequence(const std::filesystem::path& root, SeqKind kind, std::uint64_t seed = 7) {
  std::mt19937_64 rng(seed);
  // Values spread over many magnitudes so the text format must keep all 17 digits.
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-9, 6);
  auto r = [&]() { return mant(rng) * std::pow(10.0, expo(rng)); };
  auto r3 = [&]() { return Eigen::Vector3d(r(), r(), r()); };

  WrittenSequence w;
  DatasetWriter writer(root);
  const TimeNs t0 = 1403636579758555392;  // EuRoC-sized stamps (need all 64 bits)
  const int n_cams = kind == SeqKind::kMono ? 1 : 2;
  for (int c = 0; c < n_cams; ++c) {
    CameraCalib cam;
    cam.cam_id = c;
    cam.width = 752;
    cam.height = 480;
    cam.intrinsics = Eigen::Vector4d(458.654 + c, 457.296, 367.215, 248.375 + 0.1 * c);
    cam.distortion = c == 0 ? DistortionModel::kRadTan : DistortionModel::kEquidistant;
    cam.distortion_coeffs = Eigen::Vector4d(r(), r(), r(), r());
    cam.T_IC.linear() = Eigen::AngleAxisd(0.3 + c, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    cam.T_IC.translation() = r3();
    cam.timeshift_cam_imu_s = c == 0 ? 0.0 : 1.25e-3;
    cam.rate_hz = 20.0;
    writer.write_camera_calibration(cam);
    w.cameras.push_back(cam);
  }
  w.imu.gyro_noise_density = r();
  w.imu.gyro_noise_density = std::abs(w.imu.gyro_noise_density);
  w.imu.accel_random_walk = 3.3e-3;
  w.imu.T_BS.translation() = Eigen::Vector3d(0.01, -0.02, 0.03);
  writer.write_imu_calibration(w.imu);
  w.rotor.unit = "rad/s";
  w.rotor.count = 4;
  w.rotor.rate_hz = 100.0;
  w.rotor.noise_density = 0.123456789012345;
  writer.write_rotor_calibration(w.rotor);
  w.vehicle.mass_kg = 3.1015;
  w.vehicle.gravity = 9.80665;
  w.vehicle.rotor_thrust_coefficients = {2.6890e-7, 2.8190e-7, 2.7263e-7, 2.7741e-7};
  writer.write_vehicle(w.vehicle);

  std::vector<Measurement> all;
  const TimeNs dt = 5'000'000;  // 200 Hz base clock
  for (int k = 0; k < 100; ++k) {
    const TimeNs t = t0 + k * dt;
    if (k != 40 && k != 41) {  // a 15 ms IMU gap after k = 39
      ImuSample s{t, r3(), r3()};
      writer.write(s);
      all.push_back(s);
    }
    if (k % 2 == 0) {
      RotorSample rs{t, {r(), r(), r(), r()}};
      writer.write(rs);
      all.push_back(rs);
      ThrustSample ts{t + 1, std::abs(r())};  // collective thrust is never negative (the reader refuses it)
      writer.write(ts);
      all.push_back(ts);
      ForceSample fs{t, r3()};
      if (kind == SeqKind::kFeatures) {  // 7-column force0 (with its rate); the others keep 4
        fs.df_W_Nps = r3();
        fs.has_rate = true;
      }
      writer.write(fs);
      all.push_back(fs);
    }
    if (k % 10 == 3) {
      MassSample ms{t, 3.0 + std::abs(r())};
      writer.write(ms);
      all.push_back(ms);
    }
    GroundTruthSample g;
    g.t_ns = t;
    g.T_WI.p = r3();
    g.T_WI.q = Eigen::Quaterniond(Eigen::Vector4d(mant(rng), mant(rng), mant(rng), mant(rng)).normalized());
    g.v_WI = r3();
    g.b_g = r3();
    g.b_a = r3();
    writer.write(g);
    all.push_back(g);
    if (k % 10 == 0) {  // 20 Hz camera
      if (kind == SeqKind::kFeatures) {
        FeatureFrame f;
        f.t_ns = t;
        for (int i = 0; i < 6; ++i) {
          FeatureObservation o;
          o.cam_id = i % 2;
          o.feature_id = static_cast<std::uint64_t>(1000 * k + i / 2);
          o.uv = Eigen::Vector2d(752.0 * std::abs(mant(rng)), 480.0 * std::abs(mant(rng)));
          f.observations.push_back(o);
        }
        writer.write(f);
        all.push_back(f);
      } else {
        ImageFrame frame;
        frame.t_ns = t;
        for (int c = 0; c < n_cams; ++c) {
          cv::Mat img(6, 8, CV_8UC1, cv::Scalar(10 * c + k));
          writer.write_image(c, t, img);
          frame.images.push_back(ImageRef{c, (writer.mav0() / ("cam" + std::to_string(c)) / "data" /
                                              (std::to_string(t) + ".png")).string()});
        }
        all.push_back(frame);
        if (kind == SeqKind::kStereo && k == 50) {  // an unsynchronised cam1-only frame
          const TimeNs t1 = t + 2'500'000;
          writer.write_image(1, t1, cv::Mat(6, 8, CV_8UC1, cv::Scalar(3)));
          all.push_back(ImageFrame{t1, {ImageRef{1, (writer.mav0() / "cam1" / "data" /
                                                     (std::to_string(t1) + ".png")).string()}}});
        }
      }
    }
  }
  writer.close();
  std::stable_sort(all.begin(), all.end(), [](const Measurement& a, const Measurement& b) {
    const TimeNs ta = stamp_of(a), tb = stamp_of(b);
    return ta != tb ? ta < tb : merge_rank(a) < merge_rank(b);
  });
  w.expected = std::move(all);
  return w;
}

}  // namespace vid::io::test
