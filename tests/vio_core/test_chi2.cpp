// chi2 quantiles (vio_core/chi2.h) against standard table values.
#include <gtest/gtest.h>

#include <stdexcept>

#include "vio_core/chi2.h"

namespace vid {
namespace {

TEST(Chi2, QuantilesMatchTables) {
  // Standard table values of the chi-square distribution (p = 0.95 via the cache).
  EXPECT_NEAR(chi2_95(1), 3.841459, 1e-5);
  EXPECT_NEAR(chi2_95(2), 5.991465, 1e-5);
  EXPECT_NEAR(chi2_95(5), 11.070498, 1e-5);
  EXPECT_NEAR(chi2_95(10), 18.307038, 1e-5);
  EXPECT_NEAR(chi2_95(41), 56.942386, 1e-4);
  EXPECT_NEAR(chi2_95(100), 124.342113, 1e-4);
  EXPECT_NEAR(chi2_95(500), 553.126954, 1e-3);  // beyond the cached table
  EXPECT_NEAR(chi2_quantile(0.99, 3), 11.344867, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.05, 4), 0.710723, 1e-5);
  EXPECT_THROW(chi2_quantile(1.0, 3), std::invalid_argument);
  EXPECT_THROW(chi2_quantile(0.5, 0), std::invalid_argument);
}

TEST(Chi2, QuantilesAtBothGateLevels) {
  // The accelerometer gate's 99% level and larger dof than the cache holds.
  EXPECT_NEAR(chi2_quantile(0.99, 3), 11.345, 1e-3);
  EXPECT_NEAR(chi2_quantile(0.95, 1), 3.841, 1e-3);
  EXPECT_NEAR(chi2_quantile(0.95, 30), 43.773, 1e-3);
  EXPECT_NEAR(chi2_quantile(0.99, 100), 135.807, 1e-3);
  EXPECT_EQ(chi2_95(7), chi2_quantile(0.95, 7));
}

}  // namespace
}  // namespace vid
