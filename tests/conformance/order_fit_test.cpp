#include "order_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using clothlab::conformance::ErrorSample;
using clothlab::conformance::observed_order;

TEST(ObservedOrder, RecoversTheExponentOfAPowerLaw) {
  // error = 3 dt^2: halving dt quarters the error.
  EXPECT_NEAR(observed_order({{0.1, 0.03}, {0.05, 0.0075}, {0.025, 0.001875}}), 2.0, 1e-12);
  EXPECT_NEAR(observed_order({{1.0, 5.0}, {0.5, 2.5}}), 1.0, 1e-12);
}

TEST(ObservedOrder, FitsTheLeastSquaresSlope) {
  // log2 errors 0, -1, -3 at log2 dt 0, -1, -2: slope = 3/2 by hand.
  EXPECT_NEAR(observed_order({{1.0, 1.0}, {0.5, 0.5}, {0.25, 0.125}}), 1.5, 1e-12);
}

TEST(ObservedOrder, RejectsUnusableSamples) {
  EXPECT_THROW(observed_order({{0.1, 0.01}}), std::invalid_argument);
  EXPECT_THROW(observed_order({{0.1, 0.0}, {0.05, 0.01}}), std::invalid_argument);
  EXPECT_THROW(observed_order({{0.1, 0.01}, {0.1, 0.02}}), std::invalid_argument);
}
