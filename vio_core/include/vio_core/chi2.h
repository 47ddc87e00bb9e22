#pragma once
/// @file chi2.h
/// @brief Quantiles of the chi2 distribution, for the accelerometer and MSCKF gates (the one
/// definition; argument order as in scipy.stats.chi2.ppf(p, dof)).

namespace vid {

/// @brief chi2 quantile: x with P(chi2_dof <= x) = p (0 < p < 1, dof >= 1), to ~1e-12 relative.
/// @throws std::invalid_argument outside that domain
double chi2_quantile(double p, int dof);

/// @brief chi2_quantile(0.95, dof), cached for dof < 257.
double chi2_95(int dof);

}  // namespace vid
