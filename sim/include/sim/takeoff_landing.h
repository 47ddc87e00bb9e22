#pragma once
/// @file takeoff_landing.h
/// @brief Flights that start and end at rest on the ground (scenario section
/// `takeoff_landing:`, needs `ground:`): the planned timeline, the reference trajectory around
/// the scenario's own flight, and the pilot that arms, spins up, hands over to the position
/// controller, detects the touchdown, spins down and disarms.
///
/// Timeline (seconds from the start; the first ones are fixed, the rest planned back from the
/// end so that the rotors stand still for the last rest_end_s):
///
///   [0, arm)            at rest, rotors stopped (speed exactly 0)
///   [arm, spin_up)      armed: every rotor commanded to rotor_speed_min (idle)
///   [spin_up, +spin_up_s) spin-up: the position controller flies from here, its collective
///                       thrust limited by a ramp rising linearly from the idle thrust to
///                       1.25 m g over spin_up_s (then no limit). The reference starts its
///                       climb at spin_up, so the controller asks for more than the weight by
///                       the time the limit lets it: the vehicle lifts off when the thrust
///                       exceeds its weight (at ~80 % of spin_up_s), decisively.
///   [spin_up, climbed)  climb from the resting pose to the flight's start point straight
///                       above: smooth acceleration to climb_speed_mps, cruise, smooth stop;
///                       then hover_s
///   [flight, stop)      the scenario's trajectory, its own time 0 at `flight`
///   [stop, return)      the trajectory slowed down along its path to rest (time warp)
///   [return, hover)     smoothstep to the hover point above the take-off spot
///   [hover, descent)    hover_s
///   [descent, ...)      descent at descent_speed_mps (smooth start), touching the floor at
///                       `touchdown` (planned; the physics decides the actual time); the
///                       reference then stops descent_speed * 0.2 s below the resting height
///                       so that the controller keeps the gear pressed down
///   landed              the gear has touched the floor for land_detect_s: spin-down, thrust
///                       ramps (smoothstep) to 0 (idle) over spin_down_s, attitude held level
///   [disarm, end]       rotors commanded to 0; they run down with the motor lag and stop
///                       (speed set to exactly 0 below 2 % of idle), rest_end_s before the end
///
/// While the gear touches the floor the controller's integral and disturbance observer hold
/// (ControllerInput::in_contact); both restart from zero at spin_up.

#include <Eigen/Core>
#include <memory>
#include <optional>

#include "dynamics/quadrotor.h"
#include "sim/controller.h"
#include "sim/trajectory.h"

namespace vid::sim {

/// @brief `takeoff_landing:` keys (config/sim/README.md).
struct TakeoffLandingConfig {
  bool enabled = false;
  double rest_start_s = 5.0;       ///< rotors stopped at the start
  double idle_s = 1.0;             ///< at idle after arming and before disarming
  double spin_up_s = 0.5;          ///< thrust limit ramp idle -> 1.25 m g (lift-off at ~80 %)
  double climb_speed_mps = 0.5;    ///< cruise speed of the climb
  double hover_s = 1.0;            ///< hover after the climb and before the descent
  double descent_speed_mps = 0.3;  ///< final descent speed (about the touchdown speed)
  double land_detect_s = 0.2;      ///< continuous contact before the spin-down
  double spin_down_s = 1.0;        ///< thrust ramp to idle after landing
  double rest_end_s = 5.0;         ///< rotors stopped at the end
};

/// @brief Planned times [s from the start] and places of a takeoff_landing flight.
struct TakeoffLandingPlan {
  double arm_s = 0, spin_up_s = 0, spin_up_end_s = 0, climbed_s = 0, flight_s = 0, stop_s = 0, return_s = 0,
         hover_s = 0, descent_s = 0, touchdown_s = 0, disarm_s = 0;
  Eigen::Vector3d p_rest_W = Eigen::Vector3d::Zero();   ///< IMU resting on the floor (nominal)
  Eigen::Vector3d p_hover_W = Eigen::Vector3d::Zero();  ///< above the take-off spot, flight start height
  double yaw_start = 0.0;                               ///< heading on the ground at the start
};

/// @brief Fraction of rotor_speed_min below which a disarmed rotor stops (speed set to 0).
inline constexpr double kRotorStopFraction = 0.02;

/// @brief Plan the timeline around @p flight (its start point is above the take-off spot).
/// @param rest_height_m IMU height resting on the floor; @p max_speed / @p max_accel are the
/// trajectory limits (climb, stop and return respect them); @p motor_time_constant_s sets
/// how long before the end the rotors must be disarmed to be stopped for rest_end_s.
/// @throws std::invalid_argument when duration_s leaves no time to fly (names the need), or
/// when the trajectory does not start at rest at least 0.1 m above the resting height.
TakeoffLandingPlan plan_takeoff_landing(const TakeoffLandingConfig& config, const Trajectory& flight,
                                        double rest_height_m, double duration_s, double max_speed,
                                        double max_accel, double motor_time_constant_s);

/// @brief The whole reference (rest, climb, flight, stop, return, hover, descent) around
/// @p flight (planned by plan_takeoff_landing with the same @p max_accel); position is C4
/// everywhere, so the flatness feed-forward stays bounded.
std::unique_ptr<Trajectory> make_takeoff_landing_trajectory(std::unique_ptr<Trajectory> flight,
                                                            const TakeoffLandingPlan& plan,
                                                            const TakeoffLandingConfig& config, double max_accel);

/// @brief Arms, spins up, flies (through GeometricController), detects the landing, spins
/// down and disarms; call command() at every control update.
class TakeoffLandingPilot {
 public:
  /// @param armed_model the vehicle as the controller sees it (rotor_speed_min = idle).
  TakeoffLandingPilot(const TakeoffLandingConfig& config, const TakeoffLandingPlan& plan,
                      const dynamics::QuadrotorModel& armed_model);
  /// @brief Rotor speed command at in.t_s. @p weight_N is m(t) g.
  /// @throws std::runtime_error if the vehicle has not landed by the disarm time
  Eigen::VectorXd command(const ControllerInput& in, GeometricController& ctrl, const Trajectory& ref,
                          double dt_s, double weight_N);
  /// @brief Rotors commanded to 0 (before arming, after disarming).
  bool disarmed() const { return disarmed_; }
  /// @brief When the landing was detected (spin-down start) [s], if it was.
  std::optional<double> landed_s() const { return landed_s_; }

 private:
  TakeoffLandingConfig config_;
  TakeoffLandingPlan plan_;
  const dynamics::QuadrotorModel& model_;
  double idle_thrust_N_ = 0.0;
  bool disarmed_ = true;
  bool tracking_ = false;
  std::optional<double> contact_since_s_;
  std::optional<double> landed_s_;
  double landed_thrust_N_ = 0.0;
  double landed_yaw_ = 0.0;
};

}  // namespace vid::sim
