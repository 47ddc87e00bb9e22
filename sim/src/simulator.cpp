#include "sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sim/sensor_faults.h"
#include "sim/sensors.h"

namespace vid::sim {

namespace {

/// @brief Sample times t_k = start + round(k * 1e9 / rate) of one stream.
class Schedule {
 public:
  Schedule(TimeNs start, double rate_hz, bool enabled) : start_(start), rate_(rate_hz), enabled_(enabled) {}
  TimeNs next() const {
    if (!enabled_) return std::numeric_limits<TimeNs>::max();
    return start_ + static_cast<TimeNs>(std::llround(static_cast<long double>(k_) * 1e9L / rate_));
  }
  bool due(TimeNs t) const { return enabled_ && next() == t; }
  std::uint64_t index() const { return k_; }
  void advance() { ++k_; }

 private:
  TimeNs start_;
  long double rate_;
  bool enabled_;
  std::uint64_t k_ = 0;
};

constexpr std::uint64_t kImuStream = 1, kRotorStream = 2, kEnvStream = 3, kHeadingStream = 4,
                        kCameraClockStream = 6, kVibrationStream = 7, kImuStampStream = 8,
                        kRotorTelemetryStream = 9, kRotorDipStream = 10;

/// @brief Yaw of R_WI [rad] (heading of the body x-axis about z).
double yaw_of(const Eigen::Quaterniond& q_WI) {
  const Eigen::Matrix3d R = q_WI.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}

}  // namespace

Simulator::Simulator(const Scenario& scenario) : scenario_(scenario) {
  const TakeoffLandingConfig& tl = scenario_.takeoff_landing;
  const bool tilted = scenario_.faults.thrust_tilt_deg != 0.0;
  if (tl.enabled || tilted) {
    // The controller keeps idle as its lower bound while armed (the motors themselves can
    // stop), and it knows the nominal vehicle: thrust along z_I.
    armed_model_ = std::make_unique<dynamics::QuadrotorModel>(scenario_.vehicle);
    dynamics::QuadrotorParams physics = scenario_.vehicle;
    if (tl.enabled) physics.rotor_speed_min = 0.0;
    physics.thrust_axis_I = scenario_.faults.thrust_axis_I();
    model_ = std::make_unique<dynamics::QuadrotorModel>(physics);
  } else {
    model_ = std::make_unique<dynamics::QuadrotorModel>(scenario_.vehicle);
  }
  trajectory_ = make_trajectory(scenario_.trajectory);
  environment_ = std::make_unique<SimEnvironment>(scenario_.environment, scenario_.vehicle.mass_kg,
                                                  scenario_.duration_s, derive_seed(scenario_.seed, kEnvStream));
  if (tl.enabled) {
    const GroundContact& ground = *environment_->ground();
    const double rest_height =
        ground.config().gear_length_m - ground.static_sag_m(environment_->mass_kg(0.0), scenario_.vehicle.gravity);
    const TrajectoryConfig& tc = scenario_.trajectory;
    plan_ = plan_takeoff_landing(tl, *trajectory_, rest_height, scenario_.duration_s, tc.max_speed, tc.max_accel,
                                 scenario_.vehicle.motor_time_constant_s);
    trajectory_ = make_takeoff_landing_trajectory(std::move(trajectory_), *plan_, tl, tc.max_accel);
    settle_on_ground();
  }
  reset_ground_contact();
  const double yaw0_deg = yaw_of(initial_state().q_WI) * 180.0 / M_PI;
  heading_deg_ = yaw0_deg;
  if (scenario_.initial_heading_random) {
    heading_deg_ = Rng(derive_seed(scenario_.seed, kHeadingStream)).uniform(0.0, 360.0);
  } else if (scenario_.initial_heading_deg) {
    heading_deg_ = *scenario_.initial_heading_deg;
  }
  R_GS_ = Eigen::AngleAxisd((heading_deg_ - yaw0_deg) * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

Simulator::~Simulator() = default;

void Simulator::settle_on_ground() {
  constexpr double kSettleS = 2.0;  // > 100 time constants of the slowest contact mode
  dynamics::QuadrotorState x;
  x.p_WI = plan_->p_rest_W;
  x.q_WI = Eigen::Quaterniond(Eigen::AngleAxisd(plan_->yaw_start, Eigen::Vector3d::UnitZ()));
  x.rotor_speeds = Eigen::VectorXd::Zero(model_->rotor_count());
  SimEnvironment env = *environment_;  // the settling moves only this copy's friction anchors
  GroundContact ground = *env.ground();
  ground.reset_anchors(x);
  env.set_ground(ground);
  const double h = scenario_.physics_max_step_s;
  const int steps = static_cast<int>(std::ceil(kSettleS / h));
  for (int i = 0; i < steps; ++i) {  // forces held at their t = 0 values
    x = model_->rk4_step(0.0, h, x, x.rotor_speeds, env);
    env.commit_step(x);
  }
  settled_state_ = x;
  settled_ground_ = *env.ground();
}

void Simulator::reset_ground_contact() {
  if (!environment_->ground()) return;
  if (settled_ground_) {
    environment_->set_ground(*settled_ground_);
  } else {
    GroundContact g = *environment_->ground();
    g.reset_anchors(initial_state());
    environment_->set_ground(g);
  }
}

dynamics::QuadrotorState Simulator::initial_state() const {
  if (settled_state_) return *settled_state_;
  const FlatOutput r = trajectory_->eval(0.0);
  dynamics::QuadrotorState x;
  x.p_WI = r.p;
  x.v_WI = r.v;
  x.rotor_speeds = Eigen::VectorXd::Zero(model_->rotor_count());
  GeometricController ctrl(*model_, scenario_.gains);
  // The initial external force (e.g. a taut rope) depends on the state: two fixed-point passes.
  Eigen::Vector3d f_ext = environment_->force_W(0.0, x);
  Eigen::Matrix3d R;
  Eigen::Vector3d w, dw;
  for (int it = 0; it < 3; ++it) {
    ctrl.flat_attitude(*trajectory_, 0.0, f_ext, &R, &w, &dw);
    x.q_WI = Eigen::Quaterniond(R);
    x.w_I = w;
    x.rotor_speeds.setConstant(0.0);
    f_ext = model_->forces(0.0, x, *environment_).external_W();
  }
  const double m = environment_->mass_kg(0.0);
  const Eigen::Vector3d g_W(0.0, 0.0, -scenario_.vehicle.gravity);
  const Eigen::Vector3d F = m * (r.a - g_W) - f_ext;
  const Eigen::Matrix3d& J = scenario_.vehicle.inertia;
  x.rotor_speeds = ctrl.allocate(F.dot(R.col(2)), J * dw + w.cross(J * w));
  return x;
}

void Simulator::run(SimSink& sink, const std::function<void(double, double)>& progress) {
  const Scenario& sc = scenario_;
  const TimeNs t0 = sc.start_time_ns;
  const TimeNs t_end = t0 + static_cast<TimeNs>(std::llround(sc.duration_s * 1e9));
  const TimeNs max_step = static_cast<TimeNs>(std::llround(sc.physics_max_step_s * 1e9));

  Schedule imu_s(t0, sc.imu.noise.rate_hz, true);
  Schedule rotor_s(t0, sc.rotor.sensor.rate_hz, sc.rotor.enabled);
  Schedule gt_s(t0, sc.groundtruth_rate_hz, true);
  Schedule cam_s(t0, sc.cameras.rate_hz, !sc.cameras.cameras.empty());
  Schedule ctrl_s(t0, sc.control_rate_hz, true);

  ImuModel imu(sc.imu, sc.noise, derive_seed(sc.seed, kImuStream));
  RotorSensorModel rotor(sc.rotor.sensor, sc.noise, derive_seed(sc.seed, kRotorStream));
  GeometricController ctrl(control_model(), sc.gains);
  std::optional<TakeoffLandingPilot> pilot;
  if (plan_) pilot.emplace(sc.takeoff_landing, *plan_, control_model());
  const double stop_speed = kRotorStopFraction * control_model().params().rotor_speed_min;
  // Camera clock: stamp = IMU-clock time of the image - (offset + jitter).
  const bool camera_offset = sc.cameras.time_offset_s != 0.0 || sc.cameras.time_offset_jitter_s > 0.0;
  Rng camera_clock(derive_seed(sc.seed, kCameraClockStream));
  // Real-sensor effects (off unless configured: then nothing below draws a random number).
  const SensorFaultsConfig& faults = sc.faults;
  std::optional<VibrationModel> vibration;
  if (faults.vibration.enabled && sc.noise) {
    double k_sum = 0.0;
    for (const auto& r : sc.vehicle.rotors) k_sum += r.thrust_coeff;
    const double hover_speed = std::sqrt(sc.vehicle.mass_kg * sc.vehicle.gravity / k_sum);
    vibration.emplace(faults.vibration, sc.rotor_unit, hover_speed, sc.imu.noise.rate_hz, model_->rotor_count(),
                      derive_seed(sc.seed, kVibrationStream));
  }
  std::optional<ImuStampJitter> imu_stamps;
  if (faults.imu_jitter() && sc.noise)
    imu_stamps.emplace(faults.imu_jitter_s, faults.imu_max_jitter_s, sc.imu.noise.rate_hz,
                       derive_seed(sc.seed, kImuStampStream));
  std::optional<RotorTelemetry> telemetry;
  if (faults.rotor_telemetry()) telemetry.emplace(faults, sc.noise, derive_seed(sc.seed, kRotorTelemetryStream));
  const RotorDips dips(faults, model_->rotor_count(), sc.duration_s, derive_seed(sc.seed, kRotorDipStream));

  dynamics::QuadrotorState x = initial_state();
  const bool ground = environment_->ground() != nullptr;
  reset_ground_contact();
  Eigen::VectorXd n_cmd = x.rotor_speeds;
  const Eigen::Vector3d g_W(0.0, 0.0, -sc.vehicle.gravity);
  TimeNs t = t0;
  TimeNs last_ctrl = t0;
  double last_progress = -1.0;

  while (true) {
    const double ts = static_cast<double>(t - t0) * 1e-9;
    const dynamics::ForceBreakdown f = model_->forces(ts, x, *environment_);
    const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();

    // Samples at this exact physics time, all from the same state.
    if (imu_s.due(t)) {
      ImuSample s = imu.measure(t, x.w_I, R_WI.transpose() * (f.accel_W - g_W));
      if (vibration) vibration->apply(ts, x.rotor_speeds, &s);
      if (imu_stamps) s.t_ns = imu_stamps->stamp(t);
      sink.on_imu(s);
    }
    if (rotor_s.due(t)) {
      if (telemetry) {
        if (auto received = telemetry->receive(rotor.measure(t, x.rotor_speeds))) sink.on_rotor(*received);
      } else {
        sink.on_rotor(rotor.measure(t, x.rotor_speeds));
      }
      rotor_s.advance();
    }
    if (gt_s.due(t)) {
      GroundTruthSample gt;
      gt.t_ns = t;
      gt.T_WI = {x.q_WI, x.p_WI};
      gt.v_WI = x.v_WI;
      gt.b_g = imu.gyro_bias();
      gt.b_a = imu.accel_bias();
      sink.on_groundtruth(gt);
      // With the floor, the contact force's rate depends on the angular acceleration too.
      Eigen::Vector3d dw_I = Eigen::Vector3d::Zero();
      ContactWrench contact;
      if (ground) {
        dw_I = model_->derivative(ts, x, n_cmd, *environment_).w_dot;
        contact = environment_->ground_contact(x, f.accel_W, dw_I);
      }
      sink.on_force(ForceSample{t, f.external_W(),
                                external_force_rate_W(*environment_, model_->params(), ts, x, f.accel_W, dw_I), true});
      sink.on_mass(MassSample{t, f.mass_kg});
      sink.on_truth(TruthSample{t, x, f, imu.gyro_bias(), imu.accel_bias(), contact});
      if (ground) sink.on_phase({t, contact.on_ground() ? FlightPhase::kOnGround : FlightPhase::kAirborne});
      gt_s.advance();
    }
    if (imu_s.due(t)) {  // bias walks after the sample and its ground truth
      imu.step_bias();
      imu_s.advance();
    }
    if (cam_s.due(t)) {
      Eigen::Isometry3d T_WI = Eigen::Isometry3d::Identity();
      T_WI.linear() = R_WI;
      T_WI.translation() = x.p_WI;
      const BodyMotion motion{x.v_WI, f.accel_W, x.w_I};
      if (camera_offset) {
        const double jitter = sc.noise ? std::clamp(camera_clock.normal(), -3.0, 3.0) * sc.cameras.time_offset_jitter_s : 0.0;
        const double offset_s = sc.cameras.time_offset_s + jitter;
        const TimeNs stamp = t - static_cast<TimeNs>(std::llround(offset_s * 1e9));
        sink.on_camera_trigger(stamp, cam_s.index(), T_WI, motion);
        sink.on_time_offset(stamp, offset_s);
      } else {
        sink.on_camera_trigger(t, cam_s.index(), T_WI, motion);
      }
      cam_s.advance();
    }
    if (ctrl_s.due(t)) {
      ControllerInput in{ts, x, f.accel_W};
      const double dt_ctrl = static_cast<double>(t - last_ctrl) * 1e-9;
      if (ground) {
        const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
        in.in_contact = environment_->ground_contact(x, zero, zero).on_ground();
      }
      n_cmd = pilot ? pilot->command(in, ctrl, *trajectory_, dt_ctrl, f.mass_kg * sc.vehicle.gravity)
                    : ctrl.update(in, *trajectory_, dt_ctrl);
      last_ctrl = t;
      ctrl_s.advance();
    }
    if (progress && ts - last_progress >= 0.1) {
      progress(ts, sc.duration_s);
      last_progress = ts;
    }
    if (t >= t_end) break;

    TimeNs t_next = std::min({t + max_step, t_end, imu_s.next(), rotor_s.next(), gt_s.next(), cam_s.next(),
                              ctrl_s.next()});
    const double h = static_cast<double>(t_next - t) * 1e-9;
    x = model_->rk4_step(ts, h, x, dips.empty() ? n_cmd : dips.apply(ts, n_cmd), *environment_);
    if (ground) environment_->commit_step(x);
    if (pilot && pilot->disarmed()) {
      // A disarmed motor runs down and stops (the first-order lag alone would never reach 0).
      for (Eigen::Index i = 0; i < x.rotor_speeds.size(); ++i) {
        if (x.rotor_speeds[i] < stop_speed) x.rotor_speeds[i] = 0.0;
      }
    }
    t = t_next;
  }
  if (progress) progress(sc.duration_s, sc.duration_s);
}

}  // namespace vid::sim
