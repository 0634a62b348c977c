// How XPBD's two grid bands share the rows (plugins/integrators/xpbd_bands.hpp): the claims
// hand out every row exactly once, also when both bands claim at once; two bands of unequal
// speed claiming as the grid sweep does finish together, the faster with more rows; and a
// thread waiting on its predecessor learns where that one's band ended.
#include "xpbd_bands.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <thread>

namespace clothlab::builtin {
namespace {

constexpr uint32_t rows = 300, reserve = 11;  // the 300-row flag; xpbd's lag is 10

TEST(XpbdBands, ClaimsHandOutTheRowsOutsideTheReservesOnce) {
  RowClaims claims;
  claims.reset(rows, reserve);
  uint32_t granted = 0, claims_made = 0;
  for (uint32_t more = claims.claim(); more > 0; more = claims.claim()) {
    granted += more;
    ++claims_made;
  }
  EXPECT_EQ(granted, rows - 2 * reserve);
  EXPECT_EQ(claims.claim(), 0u);
  // An eighth of the rest at a time: a few dozen claims, not one per row.
  EXPECT_LT(claims_made, 60u);
  EXPECT_GT(claims_made, 8u);
}

TEST(XpbdBands, ClaimsFromTwoThreadsAtOnceSumToTheRows) {
  for (int round = 0; round < 20; ++round) {
    RowClaims claims;
    claims.reset(rows, reserve);
    std::array<uint32_t, 2> held{reserve, reserve};
    const auto band = [&](std::size_t b) {
      for (uint32_t more = claims.claim(); more > 0; more = claims.claim()) held[b] += more;
    };
    std::thread other(band, 1);
    band(0);
    other.join();
    EXPECT_EQ(held[0] + held[1], rows);
    EXPECT_GE(std::min(held[0], held[1]), reserve);
  }
}

// Two bands running `speed` rows per unit of time, each claiming when it has run through
// the rows it holds (the earlier of the two first), as grid_sweep's first threads do.
struct Outcome {
  std::array<uint32_t, 2> held;
  std::array<double, 2> finish;
};

Outcome run_bands(std::array<double, 2> speed) {
  RowClaims claims;
  claims.reset(rows, reserve);
  Outcome out{{reserve, reserve}, {0, 0}};
  std::array<bool, 2> done{false, false};
  while (!done[0] || !done[1]) {
    const auto at_end = [&](std::size_t b) { return out.held[b] / speed[b]; };
    const std::size_t b = done[0] ? 1 : done[1] ? 0 : (at_end(0) <= at_end(1) ? 0 : 1);
    const uint32_t more = claims.claim();
    if (more == 0) {
      done[b] = true;
      out.finish[b] = at_end(b);
    }
    out.held[b] += more;
  }
  return out;
}

TEST(XpbdBands, BandsOfUnequalSpeedFinishTogether) {
  for (const double slow : {1.0, 0.8, 0.5, 1.0 / 3.0}) {
    const Outcome out = run_bands({1.0, slow});
    EXPECT_EQ(out.held[0] + out.held[1], rows);
    // Fixed halves would end the slow band (1 / slow - 1) x 150 rows' time after the fast
    // one; claiming, the fast band waits at most for a few of the slow band's rows.
    EXPECT_LE(std::abs(out.finish[0] - out.finish[1]), 3.0 / slow) << "slow " << slow;
    // The rows go as the speeds: the fast band holds 1 / (1 + slow) of them.
    EXPECT_NEAR(out.held[0], rows / (1.0 + slow), 3.0) << "slow " << slow;
  }
}

TEST(XpbdBands, AWaitingThreadLearnsWhereItsPredecessorsBandEnded) {
  Progress predecessor;
  predecessor.reset();
  predecessor.completed.store(4);
  EXPECT_TRUE(wait_for(predecessor, 3));
  predecessor.end(6);
  EXPECT_TRUE(wait_for(predecessor, 5));   // time 5 was done: run it
  EXPECT_FALSE(wait_for(predecessor, 6));  // the band has no time 6: stop
  predecessor.reset();
  EXPECT_EQ(predecessor.completed.load(), 0u);
  predecessor.completed.store(1);
  EXPECT_TRUE(wait_for(predecessor, 0));  // reset: no end until the band ends again
}

}  // namespace
}  // namespace clothlab::builtin
