/// @file clone_poses.h
/// @brief The MSCKF's view of the filter's stochastic clones.
#pragma once

#include <vector>

#include "vio_core/msckf/msckf_types.h"
#include "vio_core/state.h"

namespace vid::msckf {

/// @brief Current and first-estimate poses of every clone of @p state with its covariance
/// index, in window order, as build_visual_update() takes them.
inline std::vector<ClonePose> clone_poses(const FilterState& state) {
  std::vector<ClonePose> clones;
  clones.reserve(state.clones().size());
  for (const CloneState& c : state.clones()) {
    ClonePose cp;
    cp.t_ns = c.t_ns;
    cp.R_WI = c.T_WI.R();
    cp.R_WI_fej = c.T_WI_fej.R();
    cp.p_WI = c.T_WI.p;
    cp.p_WI_fej = c.T_WI_fej.p;
    cp.cov_index = c.cov_index;
    clones.push_back(cp);
  }
  return clones;
}

}  // namespace vid::msckf
