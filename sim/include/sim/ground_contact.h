#pragma once
/// @file ground_contact.h
/// @brief The floor z = 0 as a contact plane under the landing gear: compliant normal force
/// and Coulomb friction with true sticking at each gear foot, with the contact force's
/// analytic time derivative (for force0) and its torque about the CoM.
///
/// Model choice. Each foot is a point F_i fixed in I at (+-sx, +-sy, -gear_length). Where it is
/// below the floor (compression d_i = -z_F > 0) it gets
///  * a normal force N_i = k d_i + c s(d_i) dd_i/dt >= 0 (spring-damper; the damping fades in
///    linearly over the first damping_ramp_m of compression, s = min(1, d / ramp), so the force
///    is continuous when a foot touches, as a real gear does not jump either; N is clipped at 0:
///    the floor never pulls);
///  * a tangential force from a spring-damper to a stick anchor A_i on the floor,
///    F_t = -k (F_i - A_i)_xy - c s v_xy, capped at mu N_i (Coulomb). While |F_t| < mu N_i the
///    anchor stays put: the foot sticks, a side load (a rope, a tilted thrust) deflects it by
///    F/k (~0.1 mm) and the vehicle does not creep, unlike a viscously regularised Coulomb law.
///    Beyond the cap the foot slides and the anchor is dragged along (commit()).
/// Why compliant rather than a rigid constraint: touchdown is a short finite force (seen by the
/// accelerometer and written to force0 like every other external force), the gear levels the
/// vehicle through its torques, and everything stays one smooth ODE that RK4 integrates with
/// the scenario's step. The defaults (30 kN/m, 600 N s/m for the whole gear) sag 1 mm under a
/// 3.1 kg vehicle and are about critically damped (a 16 Hz mode; omega h = 0.1 at 1 ms steps,
/// far inside RK4's stability bound of 2.8): a 0.3 m/s touchdown stops within 1.3 mm, peaking
/// at ~5 g, without a bounce. (Less damping, 400 N s/m, bounced off for 30 ms: a clipped
/// spring-damper gives back ~13 % of the touchdown speed at critical damping, more below it.)
/// The anchors are the only state outside QuadrotorState: they are held fixed within a step
/// (all four RK4 stages see the same ones) and updated by commit() after it.

#include <Eigen/Core>
#include <vector>

#include "dynamics/quadrotor.h"

namespace vid::sim {

/// @brief Landing gear and floor (scenario section `ground:`).
struct GroundContactConfig {
  bool enabled = false;
  /// IMU height above the floor with the gear unloaded [m]; resting, the IMU is the static
  /// compression m g / stiffness lower (default 0.111 m -> the IMU rests at 0.110 m).
  double gear_length_m = 0.111;
  Eigen::Vector2d gear_half_span_m{0.2, 0.2};  ///< feet at (+-x, +-y, -gear_length) in I [m]
  double stiffness_N_per_m = 30000.0;          ///< whole gear (each of the 4 feet: 1/4), normal and tangential
  double damping_Ns_per_m = 600.0;             ///< whole gear, normal and tangential
  double damping_ramp_m = 0.0005;              ///< damping fades in over this compression [m]
  double friction_coefficient = 0.6;           ///< Coulomb mu (static = kinetic)
};

/// @brief The ground's force on the vehicle at one instant.
struct ContactWrench {
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();    ///< total contact force [N, W]
  Eigen::Vector3d df_W = Eigen::Vector3d::Zero();   ///< its time derivative [N/s, W]
  Eigen::Vector3d tau_I = Eigen::Vector3d::Zero();  ///< torque about the CoM [N m, I]
  double normal_N = 0.0;                            ///< sum of the normal forces [N]
  /// Feet touching the floor (at or below z = 0, compressing the gear). A touching foot may
  /// carry no force for a moment: the damper cannot pull, so a foot lifting off fast is
  /// unloaded (N clipped at 0) before it leaves the floor. A foot off the floor never carries any.
  int feet_touching = 0;
  int feet_loaded = 0;                              ///< touching feet with a normal force > 0
  int feet_sliding = 0;                             ///< loaded feet at the friction cap
  /// @brief The vehicle stands on the floor (phase on_ground): some foot touches it.
  bool on_ground() const { return feet_touching > 0; }
};

/// @brief Floor contact of the landing gear; copyable (the stick anchors are its state).
class GroundContact {
 public:
  /// @brief Anchors start at the origin: call reset_anchors() (or copy a settled contact)
  /// before evaluating. @throws std::invalid_argument on non-physical parameters (names the key)
  explicit GroundContact(const GroundContactConfig& config);
  /// @brief Contact force, rate and torque at state x. @p a_W (acceleration) and @p dw_I
  /// (angular acceleration) only enter the rate; pass zeros when only the force is needed.
  ContactWrench evaluate(const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                         const Eigen::Vector3d& dw_I) const;
  /// @brief After an accepted integration step: feet off the floor put their anchor under
  /// themselves, sliding feet drag it to the friction cap, sticking feet keep it.
  void commit(const dynamics::QuadrotorState& x);
  /// @brief Put every anchor under its foot (no tangential preload), e.g. before settling.
  void reset_anchors(const dynamics::QuadrotorState& x);
  /// @brief Foot positions in I.
  const std::vector<Eigen::Vector3d>& feet_I() const { return feet_I_; }
  /// @brief Stick anchors on the floor [m, W xy], one per foot.
  const std::vector<Eigen::Vector2d>& anchors_W() const { return anchors_W_; }
  /// @brief Static compression of the gear under weight m g, level and evenly loaded [m].
  double static_sag_m(double mass_kg, double gravity) const;
  const GroundContactConfig& config() const { return config_; }

 private:
  GroundContactConfig config_;
  std::vector<Eigen::Vector3d> feet_I_;
  std::vector<Eigen::Vector2d> anchors_W_;
  double k_foot_ = 0.0, c_foot_ = 0.0;
};

}  // namespace vid::sim
