#pragma once
/// @file simulator.h
/// @brief The simulation loop: RK4 physics stepping exactly onto every sensor time (so every
/// sample is taken from the continuous physics at its own time), the controller at its rate,
/// and the sensor models; results go to a SimSink.

#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <optional>

#include "dynamics/quadrotor.h"
#include "sim/controller.h"
#include "sim/environment.h"
#include "sim/ground_contact.h"
#include "sim/scenario.h"
#include "sim/takeoff_landing.h"
#include "sim/trajectory.h"
#include "types/measurements.h"

namespace vid::sim {

/// @brief Full truth at a ground-truth time (for tests and tools; not written to disk).
struct TruthSample {
  TimeNs t_ns = 0;
  dynamics::QuadrotorState state;
  dynamics::ForceBreakdown forces;
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();
  /// Ground reaction alone (part of forces.env_W and of force0), its rate and torque; zero
  /// without `ground:`.
  ContactWrench ground;
};

/// @brief Contact phase of the vehicle (phase0/data.csv, docs/formats.md §1).
enum class FlightPhase : int {
  kOnGround = 0,  ///< at least one gear foot touches the floor (ContactWrench::on_ground)
  kAirborne = 1,  ///< no foot touches the floor: the ground reaction is exactly 0
};

/// @brief The contact phase at a ground-truth time (only with `ground:`).
struct PhaseSample {
  TimeNs t_ns = 0;
  FlightPhase phase = FlightPhase::kAirborne;
};

/// @brief Body motion at a camera trigger: what an image's exposure (motion blur, rolling
/// shutter) integrates over; the pose at t + dt is extrapolated from it (|dt| of milliseconds).
struct BodyMotion {
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();  ///< velocity of I in W [m/s]
  Eigen::Vector3d a_WI = Eigen::Vector3d::Zero();  ///< acceleration of I in W [m/s^2]
  Eigen::Vector3d w_I = Eigen::Vector3d::Zero();   ///< angular velocity in I [rad/s]
};

/// @brief Receiver of everything the simulator produces (all methods optional).
class SimSink {
 public:
  virtual ~SimSink() = default;
  virtual void on_imu(const ImuSample&) {}
  virtual void on_rotor(const RotorSample&) {}
  virtual void on_groundtruth(const GroundTruthSample&) {}
  virtual void on_force(const ForceSample&) {}
  virtual void on_mass(const MassSample&) {}
  virtual void on_truth(const TruthSample&) {}
  /// @brief Contact phase at every ground-truth time, only when the scenario has `ground:`.
  virtual void on_phase(const PhaseSample&) {}
  /// @brief A camera trigger: body pose at the image time (cameras via their T_IC). @p t_ns is
  /// the camera's stamp: the image's IMU-clock time minus the camera-IMU time offset.
  virtual void on_camera(TimeNs /*t_ns*/, std::uint64_t /*frame_index*/, const Eigen::Isometry3d& /*T_WI*/) {}
  /// @brief The camera trigger as the simulator sends it: on_camera plus the body motion at
  /// that time (for exposures). The default forwards to on_camera.
  virtual void on_camera_trigger(TimeNs t_ns, std::uint64_t frame_index, const Eigen::Isometry3d& T_WI,
                                 const BodyMotion& /*motion*/) {
    on_camera(t_ns, frame_index, T_WI);
  }
  /// @brief The true offset of the frame stamped @p t_ns (t_imu = t_cam + offset), only when the
  /// scenario has `cameras.time_offset_s` or `time_offset_jitter_s`.
  virtual void on_time_offset(TimeNs /*t_ns*/, double /*offset_s*/) {}
};

/// @brief Runs one scenario.
class Simulator {
 public:
  explicit Simulator(const Scenario& scenario);
  ~Simulator();
  /// @brief Simulate [0, duration]; progress(done_s, total_s) is called every ~0.1 s of
  /// simulated time.
  void run(SimSink& sink, const std::function<void(double, double)>& progress = {});

  const Scenario& scenario() const { return scenario_; }
  /// @brief The vehicle as integrated (with `takeoff_landing:` its rotor_speed_min is 0: a
  /// disarmed rotor stops; with `sensor_faults.thrust_axis` its thrust axis is tilted).
  const dynamics::QuadrotorModel& model() const { return *model_; }
  const Trajectory& trajectory() const { return *trajectory_; }
  /// @brief The environment; with `ground:` its friction anchors are those of t = 0 before
  /// run() and those of the end after it.
  const SimEnvironment& environment() const { return *environment_; }
  /// @brief State at t = 0: on the reference, with attitude, body rate and rotor speeds
  /// that realise the reference acceleration against the initial external force; with
  /// `takeoff_landing:` resting on the floor with the rotors stopped (settled, see below).
  dynamics::QuadrotorState initial_state() const;
  /// @brief The planned timeline with `takeoff_landing:`, else nullopt.
  const std::optional<TakeoffLandingPlan>& takeoff_landing_plan() const { return plan_; }
  /// @brief Heading of the vehicle at t = 0 in the written ground-truth world [deg]: the
  /// scenario's initial_heading_deg (drawn from the seed when random), else the trajectory's.
  double initial_heading_deg() const { return heading_deg_; }
  /// @brief R_GS: rotation about z from the simulation world (where trajectory, forces and
  /// scene live, and in which every SimSink receives its data) to the ground-truth world
  /// that DatasetSink writes. Identity unless the scenario sets an initial heading.
  const Eigen::Matrix3d& R_GS() const { return R_GS_; }

 private:
  Scenario scenario_;
  /// @brief Rest the vehicle on the floor: level at the planned resting pose, rotors stopped,
  /// integrated until every transient has died out, so that at t = 0 it is truly still under
  /// whatever side load acts (the friction anchors carry it).
  void settle_on_ground();
  /// @brief Put the environment's friction anchors where they are at t = 0 (settled, or
  /// under the feet), so environment() is the t = 0 one before and at the start of run().
  void reset_ground_contact();
  const dynamics::QuadrotorModel& control_model() const { return armed_model_ ? *armed_model_ : *model_; }

  std::unique_ptr<dynamics::QuadrotorModel> model_;
  /// The controller's view of the vehicle (idle minimum, nominal thrust axis); only with
  /// takeoff_landing or a thrust-axis tilt.
  std::unique_ptr<dynamics::QuadrotorModel> armed_model_;
  std::unique_ptr<Trajectory> trajectory_;
  std::optional<TakeoffLandingPlan> plan_;
  std::optional<dynamics::QuadrotorState> settled_state_;
  std::optional<GroundContact> settled_ground_;
  std::unique_ptr<SimEnvironment> environment_;
  double heading_deg_ = 0.0;
  Eigen::Matrix3d R_GS_ = Eigen::Matrix3d::Identity();
};

}  // namespace vid::sim
