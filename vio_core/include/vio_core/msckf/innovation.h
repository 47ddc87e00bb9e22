#pragma once
/// @file innovation.h
/// @brief Innovation covariance S = H_x P_T H_x^T of one feature from the block structure of
/// H_x: every observation contributes a 2x6 block at its clone (and optionally a 2x6 block at
/// its camera extrinsic), so only those 6x6 blocks of P_T are read.

#include <Eigen/Core>
#include <vector>

namespace vid::msckf {

/// @brief Jacobian blocks of one observation (two rows of H_x) in a compact column layout.
struct ObservationBlocks {
  int clone_col = 0;  ///< first column of the clone block in P_T
  int ext_col = -1;   ///< first column of the extrinsic block in P_T, -1 if not estimated
  Eigen::Matrix<double, 2, 6> H_clone = Eigen::Matrix<double, 2, 6>::Zero();
  Eigen::Matrix<double, 2, 6> H_ext = Eigen::Matrix<double, 2, 6>::Zero();
};

/// @brief Reusable buffers of innovation_covariance_lower (no allocation once warmed up).
/// After a call, block_col / local_clone / local_ext describe the feature's blocks.
struct InnovationScratch {
  std::vector<int> block_col;    ///< distinct 6-column blocks the feature touches, ascending
  std::vector<int> order;        ///< block_col before sorting
  std::vector<int> local_clone;  ///< per observation: index into block_col
  std::vector<int> local_ext;    ///< per observation: index into block_col or -1
  Eigen::MatrixXd P_f;           ///< touched blocks of P_T, when not consecutive in P_T
  Eigen::MatrixXd PHt;           ///< (6 * blocks) x 2m: rows of P_T H_x^T at those blocks
  Eigen::Matrix<double, Eigen::Dynamic, 6> H_c;  ///< stacked clone Jacobians (2m x 6)
  std::vector<int> group_start;  ///< first observation of each clone group, then m
};

/// @brief Lower triangle (including the full 2x2 diagonal blocks) of S = H_x P_T H_x^T,
/// 2m x 2m for m observations; P_T symmetric (only its touched 6x6 blocks are read). The
/// strictly upper part of S outside the diagonal blocks is left unspecified.
/// Without extrinsic blocks, S is built from clone-group blocks H_g P_gh H_h^T (fixed-size
/// for mono / stereo groups); otherwise from P_T H_x^T on the touched blocks. Either way
/// O(m^2 * 100) flops instead of dense products over all of P_T.
void innovation_covariance_lower(const Eigen::MatrixXd& P_T,
                                 const std::vector<ObservationBlocks>& obs, Eigen::MatrixXd* S,
                                 InnovationScratch* scratch);

}  // namespace vid::msckf
