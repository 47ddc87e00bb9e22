/// @file innovation.cpp
/// @brief Block-sparse innovation covariance of one MSCKF feature.

#include "vio_core/msckf/innovation.h"

#include <algorithm>
#include <cstddef>

namespace vid::msckf {
namespace {

/// Index of col in blocks, appending it if new (a feature touches few blocks).
int local_block(std::vector<int>* blocks, int col) {
  const auto it = std::find(blocks->begin(), blocks->end(), col);
  if (it != blocks->end()) return static_cast<int>(it - blocks->begin());
  blocks->push_back(col);
  return static_cast<int>(blocks->size()) - 1;
}

}  // namespace

void innovation_covariance_lower(const Eigen::MatrixXd& P_T,
                                 const std::vector<ObservationBlocks>& obs, Eigen::MatrixXd* S,
                                 InnovationScratch* scratch) {
  const int m = static_cast<int>(obs.size());
  InnovationScratch& w = *scratch;
  w.block_col.clear();
  w.local_clone.resize(obs.size());
  w.local_ext.resize(obs.size());
  for (int a = 0; a < m; ++a) {
    w.local_clone[a] = local_block(&w.block_col, obs[a].clone_col);
    w.local_ext[a] = obs[a].ext_col >= 0 ? local_block(&w.block_col, obs[a].ext_col) : -1;
  }
  const int nb = static_cast<int>(w.block_col.size());
  // Ascending column order so that consecutive blocks can be read in place.
  if (!std::is_sorted(w.block_col.begin(), w.block_col.end())) {
    w.order = w.block_col;
    std::sort(w.block_col.begin(), w.block_col.end());
    const auto rank = [&](int old) {
      return static_cast<int>(std::lower_bound(w.block_col.begin(), w.block_col.end(),
                                               w.order[old]) - w.block_col.begin());
    };
    for (int a = 0; a < m; ++a) {
      w.local_clone[a] = rank(w.local_clone[a]);
      if (w.local_ext[a] >= 0) w.local_ext[a] = rank(w.local_ext[a]);
    }
  }

  // The touched blocks of P_T as one contiguous symmetric matrix: a view when they are
  // consecutive in P_T (the usual full-window case), else gathered.
  bool consecutive = true;
  for (int i = 1; i < nb; ++i) consecutive &= w.block_col[i] == w.block_col[0] + 6 * i;
  if (!consecutive) {
    w.P_f.resize(6 * nb, 6 * nb);
    for (int j = 0; j < nb; ++j) {
      for (int i = 0; i < nb; ++i) {
        w.P_f.block<6, 6>(6 * i, 6 * j) = P_T.block<6, 6>(w.block_col[i], w.block_col[j]);
      }
    }
  }
  const Eigen::MatrixXd& src = consecutive ? P_T : w.P_f;
  const int first = consecutive ? w.block_col[0] : 0;
  const auto P_f = src.block(first, first, 6 * nb, 6 * nb);

  // P_f H_x^T: per observation two columns = (6 columns of P_f) * (6x2), coefficient-based so
  // the 6-term sums vectorize down the rows.
  w.PHt.resize(6 * nb, 2 * m);
  for (int a = 0; a < m; ++a) {
    auto dst = w.PHt.middleCols<2>(2 * a);
    dst.noalias() = P_f.middleCols<6>(6 * w.local_clone[a]).lazyProduct(obs[a].H_clone.transpose());
    if (w.local_ext[a] >= 0) {
      dst.noalias() += P_f.middleCols<6>(6 * w.local_ext[a]).lazyProduct(obs[a].H_ext.transpose());
    }
  }

  // S(a, b) = H_a (P_T H_x^T)(block of a, cols of b) for a >= b.
  S->resize(2 * m, 2 * m);
  for (int b = 0; b < m; ++b) {
    for (int a = b; a < m; ++a) {
      auto dst = S->block<2, 2>(2 * a, 2 * b);
      dst.noalias() = obs[a].H_clone * w.PHt.block<6, 2>(6 * w.local_clone[a], 2 * b);
      if (w.local_ext[a] >= 0) {
        dst.noalias() += obs[a].H_ext * w.PHt.block<6, 2>(6 * w.local_ext[a], 2 * b);
      }
    }
  }
}

}  // namespace vid::msckf
