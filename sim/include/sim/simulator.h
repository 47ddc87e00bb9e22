#pragma once
/// @file simulator.h
/// @brief The simulation loop: RK4 physics stepping exactly onto every sensor time (so every
/// sample is taken from the continuous physics at its own time), the controller at its rate,
/// and the sensor models; results go to a SimSink.

#include <Eigen/Geometry>
#include <functional>
#include <memory>

#include "dynamics/quadrotor.h"
#include "sim/controller.h"
#include "sim/environment.h"
#include "sim/scenario.h"
#include "sim/trajectory.h"
#include "vio_core/measurements.h"

namespace vid::sim {

/// @brief Full truth at a ground-truth time (for tests and tools; not written to disk).
struct TruthSample {
  TimeNs t_ns = 0;
  dynamics::QuadrotorState state;
  dynamics::ForceBreakdown forces;
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();
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
  /// @brief A camera trigger: body pose at the image time (cameras via their T_IC).
  virtual void on_camera(TimeNs /*t_ns*/, std::uint64_t /*frame_index*/, const Eigen::Isometry3d& /*T_WI*/) {}
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
  const dynamics::QuadrotorModel& model() const { return *model_; }
  const Trajectory& trajectory() const { return *trajectory_; }
  const SimEnvironment& environment() const { return *environment_; }
  /// @brief State at t = 0: on the reference, with attitude, body rate and rotor speeds
  /// that realise the reference acceleration against the initial external force.
  dynamics::QuadrotorState initial_state() const;
  /// @brief Heading of the vehicle at t = 0 in the written ground-truth world [deg]: the
  /// scenario's initial_heading_deg (drawn from the seed when random), else the trajectory's.
  double initial_heading_deg() const { return heading_deg_; }
  /// @brief R_GS: rotation about z from the simulation world (where trajectory, forces and
  /// scene live, and in which every SimSink receives its data) to the ground-truth world
  /// that DatasetSink writes. Identity unless the scenario sets an initial heading.
  const Eigen::Matrix3d& R_GS() const { return R_GS_; }

 private:
  Scenario scenario_;
  std::unique_ptr<dynamics::QuadrotorModel> model_;
  std::unique_ptr<Trajectory> trajectory_;
  std::unique_ptr<SimEnvironment> environment_;
  double heading_deg_ = 0.0;
  Eigen::Matrix3d R_GS_ = Eigen::Matrix3d::Identity();
};

}  // namespace vid::sim
