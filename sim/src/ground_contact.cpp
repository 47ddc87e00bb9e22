/// @file ground_contact.cpp
/// @brief Floor contact of the landing gear (model and its reasons: ground_contact.h).

#include "sim/ground_contact.h"

#include <cmath>
#include <stdexcept>

namespace vid::sim {

namespace {

/// @brief One foot's kinematics in W: position, velocity, acceleration.
struct FootMotion {
  Eigen::Vector3d p_WF, v_WF, a_WF;
};

FootMotion foot_motion(const dynamics::QuadrotorState& x, const Eigen::Matrix3d& R_WI, const Eigen::Vector3d& r_I,
                       const Eigen::Vector3d& a_W, const Eigen::Vector3d& dw_I) {
  const Eigen::Vector3d& w = x.w_I;
  return {x.p_WI + R_WI * r_I, x.v_WI + R_WI * w.cross(r_I),
          a_W + R_WI * (dw_I.cross(r_I) + w.cross(w.cross(r_I)))};
}

/// @brief One foot's force [N, W] and rate; `sliding` when the friction cap acts.
struct FootForce {
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero(), df_W = Eigen::Vector3d::Zero();
  bool touching = false, sliding = false;
};

}  // namespace

GroundContact::GroundContact(const GroundContactConfig& c) : config_(c) {
  if (!(c.gear_length_m > 0.0)) throw std::invalid_argument("ground: gear_length_m must be > 0");
  if (!(c.gear_half_span_m.minCoeff() > 0.0)) throw std::invalid_argument("ground: gear_half_span_m must be > 0");
  if (!(c.stiffness_N_per_m > 0.0)) throw std::invalid_argument("ground: stiffness_N_per_m must be > 0");
  if (!(c.damping_Ns_per_m >= 0.0)) throw std::invalid_argument("ground: damping_Ns_per_m must be >= 0");
  if (!(c.damping_ramp_m >= 0.0)) throw std::invalid_argument("ground: damping_ramp_m must be >= 0");
  if (!(c.friction_coefficient >= 0.0)) throw std::invalid_argument("ground: friction_coefficient must be >= 0");
  const double sx = c.gear_half_span_m.x(), sy = c.gear_half_span_m.y(), h = c.gear_length_m;
  feet_I_ = {{sx, sy, -h}, {-sx, sy, -h}, {-sx, -sy, -h}, {sx, -sy, -h}};
  anchors_W_.assign(feet_I_.size(), Eigen::Vector2d::Zero());
  k_foot_ = c.stiffness_N_per_m / static_cast<double>(feet_I_.size());
  c_foot_ = c.damping_Ns_per_m / static_cast<double>(feet_I_.size());
}

double GroundContact::static_sag_m(double mass_kg, double gravity) const {
  return mass_kg * gravity / config_.stiffness_N_per_m;
}

ContactWrench GroundContact::evaluate(const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                                      const Eigen::Vector3d& dw_I) const {
  ContactWrench out;
  const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();
  const double ramp = config_.damping_ramp_m, mu = config_.friction_coefficient;
  for (std::size_t i = 0; i < feet_I_.size(); ++i) {
    const FootMotion m = foot_motion(x, R_WI, feet_I_[i], a_W, dw_I);
    // Compression d = -z (floor at z = 0) and its derivatives.
    const double d = -m.p_WF.z(), dd = -m.v_WF.z(), ddd = -m.a_WF.z();
    if (!(d > 0.0)) continue;
    ++out.feet_touching;
    const bool in_ramp = ramp > 0.0 && d < ramp;
    const double s = in_ramp ? d / ramp : 1.0;        // damping fade
    const double ds = in_ramp ? 1.0 / ramp : 0.0;     // d s / d d
    const double N = k_foot_ * d + c_foot_ * s * dd;
    if (!(N > 0.0)) continue;  // separating faster than the spring pushes: the floor never pulls
    const double dN = k_foot_ * dd + c_foot_ * (ds * dd * dd + s * ddd);
    FootForce f;
    f.touching = true;
    // Stick spring-damper to the anchor, capped at mu N (Coulomb).
    const Eigen::Vector2d defl = m.p_WF.head<2>() - anchors_W_[i];
    const Eigen::Vector2d Fs = -k_foot_ * defl - c_foot_ * s * m.v_WF.head<2>();
    const Eigen::Vector2d dFs =
        -k_foot_ * m.v_WF.head<2>() - c_foot_ * (ds * dd * m.v_WF.head<2>() + s * m.a_WF.head<2>());
    const double cap = mu * N, norm = Fs.norm();
    Eigen::Vector2d Ft = Fs, dFt = dFs;
    if (norm > cap) {  // sliding: |F_t| = mu N along the spring's pull
      const Eigen::Vector2d u = Fs / norm;
      Ft = cap * u;
      dFt = mu * dN * u + cap * (dFs - u * u.dot(dFs)) / norm;
      f.sliding = true;
    }
    f.f_W << Ft, N;
    f.df_W << dFt, dN;
    out.f_W += f.f_W;
    out.df_W += f.df_W;
    out.tau_I += feet_I_[i].cross(R_WI.transpose() * f.f_W);
    out.normal_N += N;
    ++out.feet_loaded;
    if (f.sliding) ++out.feet_sliding;
  }
  return out;
}

void GroundContact::commit(const dynamics::QuadrotorState& x) {
  const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const double ramp = config_.damping_ramp_m, mu = config_.friction_coefficient;
  for (std::size_t i = 0; i < feet_I_.size(); ++i) {
    const FootMotion m = foot_motion(x, R_WI, feet_I_[i], zero, zero);
    const double d = -m.p_WF.z(), dd = -m.v_WF.z();
    const double s = (ramp > 0.0 && d < ramp) ? d / ramp : 1.0;
    const double N = d > 0.0 ? k_foot_ * d + c_foot_ * s * dd : 0.0;
    const Eigen::Vector2d p = m.p_WF.head<2>();
    if (!(N > 0.0)) {
      anchors_W_[i] = p;  // in the air: the next touch starts without preload
      continue;
    }
    const Eigen::Vector2d defl = p - anchors_W_[i];
    const double limit = mu * N / k_foot_;  // largest elastic deflection that sticks
    if (defl.norm() > limit) anchors_W_[i] = p - defl.normalized() * limit;
  }
}

void GroundContact::reset_anchors(const dynamics::QuadrotorState& x) {
  const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();
  for (std::size_t i = 0; i < feet_I_.size(); ++i) anchors_W_[i] = (x.p_WI + R_WI * feet_I_[i]).head<2>();
}

}  // namespace vid::sim
