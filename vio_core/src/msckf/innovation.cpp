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

/// S block of clone groups (g, h): H_g P_gh H_h^T with H_g the stacked clone Jacobians of
/// the observations of group g (RG rows; Eigen::Dynamic for an unusual count).
template <int RG, int RH>
void group_block(const Eigen::MatrixXd& P_T, const Eigen::Matrix<double, Eigen::Dynamic, 6>& H_c,
                 int row_g, int rows_g, int col_g, int row_h, int rows_h, int col_h,
                 Eigen::MatrixXd* S) {
  using MatG = Eigen::Matrix<double, RG, 6>;  // heap only for an unusual group size
  const MatG T = H_c.middleRows(row_g, rows_g) * P_T.block<6, 6>(col_g, col_h);
  if constexpr (RH == Eigen::Dynamic || RG == Eigen::Dynamic) {
    S->block(row_g, row_h, rows_g, rows_h).noalias() =
        T.lazyProduct(H_c.middleRows(row_h, rows_h).transpose());
  } else {
    const Eigen::Matrix<double, 6, RH> H_hT = H_c.middleRows<RH>(row_h).transpose();
    S->block<RG, RH>(row_g, row_h).noalias() = T * H_hT;
  }
}

/// S for features without estimated extrinsics as a grid of blocks H_g P_gh H_h^T over
/// groups of consecutive observations of one clone (tracks are sorted by time, so a group is
/// all observations of a clone; the formula holds for any grouping). Stereo gives 4-row
/// groups that map onto fixed-size products.
void grouped_clone_covariance(const Eigen::MatrixXd& P_T, const std::vector<ObservationBlocks>& obs,
                              Eigen::MatrixXd* S, InnovationScratch* scratch) {
  const int m = static_cast<int>(obs.size());
  InnovationScratch& w = *scratch;
  w.H_c.resize(2 * m, 6);
  w.group_start.clear();
  for (int a = 0; a < m; ++a) {
    w.H_c.middleRows<2>(2 * a) = obs[a].H_clone;
    if (a == 0 || obs[a].clone_col != obs[a - 1].clone_col) w.group_start.push_back(a);
  }
  const int ng = static_cast<int>(w.group_start.size());
  w.group_start.push_back(m);
  S->resize(2 * m, 2 * m);
  for (int h = 0; h < ng; ++h) {
    const int row_h = 2 * w.group_start[h];
    const int rows_h = 2 * w.group_start[h + 1] - row_h;
    const int col_h = obs[w.group_start[h]].clone_col;
    for (int g = h; g < ng; ++g) {
      const int row_g = 2 * w.group_start[g];
      const int rows_g = 2 * w.group_start[g + 1] - row_g;
      const int col_g = obs[w.group_start[g]].clone_col;
      if (rows_g == 4 && rows_h == 4) {
        group_block<4, 4>(P_T, w.H_c, row_g, rows_g, col_g, row_h, rows_h, col_h, S);
      } else if (rows_g == 2 && rows_h == 2) {
        group_block<2, 2>(P_T, w.H_c, row_g, rows_g, col_g, row_h, rows_h, col_h, S);
      } else {
        group_block<Eigen::Dynamic, Eigen::Dynamic>(P_T, w.H_c, row_g, rows_g, col_g, row_h,
                                                    rows_h, col_h, S);
      }
    }
  }
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

  // Clone-group fast path when no observation touches an extrinsic block.
  bool grouped = true;
  for (int a = 0; a < m; ++a) grouped &= obs[a].ext_col < 0;
  if (grouped) {
    grouped_clone_covariance(P_T, obs, S, scratch);
    return;
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
