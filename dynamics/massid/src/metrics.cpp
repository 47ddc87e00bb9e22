/// @file metrics.cpp
/// @brief Scores shared by every mass-identification method.
#include <cmath>
#include <stdexcept>

#include "massid/estimator.h"

namespace vid::massid {

double rmspe(const std::vector<double>& m_hat, const std::vector<double>& m) {
  if (m_hat.empty() || m_hat.size() != m.size()) {
    throw std::invalid_argument("rmspe: needs two non-empty sequences of equal length");
  }
  double sum = 0.0;
  for (size_t k = 0; k < m.size(); ++k) {
    const double e = (m_hat[k] - m[k]) / m[k];
    sum += e * e;
  }
  return std::sqrt(sum / static_cast<double>(m.size())) * 100.0;
}

}  // namespace vid::massid
