#pragma once
/// @file fixed_lag.h
/// @brief Fixed-lag smoothed outputs of the force (and pose) from the filter's force clones
/// (FilterState::augment_force_clone; docs/notes/smoothing.md, docs/model.md eqs. (35)-(40)).
///
/// A force clone taken at camera time t_k is corrected by every later update through its
/// cross-covariance; when it leaves the window (t_k + lag) it is the smoothed estimate
/// F(t_k | t_k + lag). Its correction against the causal estimate of t_k (the clone's value
/// and covariance right after the frame at t_k was processed, eq. (38)) is an anchor; the
/// pose anchor is the pose clone of the same time, read when the force clone leaves or, if the
/// MSCKF window dropped it earlier, when it was marginalized (pose lag min(lag, window)).
/// IMU-rate estimates between two anchors get the linearly interpolated correction (eq. (39)).

#include <Eigen/Core>
#include <deque>
#include <functional>
#include <optional>

#include "geometry/pose.h"
#include "vio_core/estimator_outputs.h"

namespace vid {

/// @brief Correction of the smoothed estimate of one clone time against the causal one.
struct LagAnchor {
  TimeNs t_ns = 0;
  Eigen::Vector3d dF = Eigen::Vector3d::Zero();      ///< smoothed - causal F_ext (force frame) [m/s^2]
  Eigen::Matrix3d dP_F = Eigen::Matrix3d::Zero();    ///< causal - smoothed cov of F_ext (force frame)
  Eigen::Vector3d dtheta = Eigen::Vector3d::Zero();  ///< Log(R_WI_causal^T R_WI_smoothed) [rad]
  Eigen::Vector3d dp_WI = Eigen::Vector3d::Zero();   ///< smoothed - causal p_WI [m]
};

/// @brief Buffers IMU-rate causal estimates and emits them smoothed once the anchors around
/// them are known. Memory: (lag + clone period) of estimates and a few anchors.
class FixedLagOutput {
 public:
  explicit FixedLagOutput(ForceFrame frame) : frame_(frame) {}

  /// @brief A force clone was taken at @p t_ns: remember its causal value (F_ext_fc in the
  /// force frame and covariance P_F; the pose clone of that time, T_WI) after the frame's update.
  void clone_taken(TimeNs t_ns, const Eigen::Vector3d& F_ext_fc, const Eigen::Matrix3d& P_F, const Pose& T_WI);
  /// @brief The pose clone of @p t_ns leaves the MSCKF window with value @p T_WI (kept as the
  /// smoothed pose of that time if a force clone of the same time is pending).
  void pose_leaving(TimeNs t_ns, const Pose& T_WI);
  /// @brief The force clone of @p t_ns leaves: its smoothed value and covariance; T_WI the
  /// pose clone of that time if still in the window (else the one recorded by pose_leaving).
  void clone_released(TimeNs t_ns, const Eigen::Vector3d& F_ext_fc, const Eigen::Matrix3d& P_F,
                      const std::optional<Pose>& T_WI);
  /// @brief A causal IMU-rate estimate (time order).
  void add_causal(const EstimateOutput& e) { causal_.push_back(e); }
  /// @brief Emit (smoothed) every buffered estimate up to the newest anchor; all of them with
  /// @p all (end of stream: the last anchor's correction held).
  void release(const std::function<void(const EstimateOutput&)>& out, bool all = false);
  /// @brief Causal estimates and pending clones held (memory check).
  std::size_t buffered() const { return causal_.size() + pending_.size() + anchors_.size(); }

 private:
  struct Pending {
    TimeNs t_ns = 0;
    Eigen::Vector3d F_ext_fc;
    Eigen::Matrix3d P_F;
    Pose T_WI;                     ///< causal pose
    std::optional<Pose> T_WI_last;  ///< pose clone's value when it left the MSCKF window
  };
  EstimateOutput smoothed(const EstimateOutput& e) const;

  ForceFrame frame_;
  std::deque<Pending> pending_;
  std::deque<LagAnchor> anchors_;  ///< the two around the oldest buffered estimate
  std::deque<EstimateOutput> causal_;
};

/// @brief Apply @p a (force frame @p frame) to a causal estimate: F_ext, T_WI, the force in
/// both frames and its covariance (eqs. (39)-(40) with the anchor's values).
EstimateOutput apply_lag_anchor(const EstimateOutput& e, const LagAnchor& a, ForceFrame frame);

/// @brief The anchor at time t between a and b (linear in time; b alone if t >= b.t_ns,
/// a alone if t <= a.t_ns).
LagAnchor interpolate_anchor(const LagAnchor& a, const LagAnchor& b, TimeNs t);

}  // namespace vid
