// The robust stretch figures (issue 21) on hand-built cloths whose spring lengths are known
// exactly: the nearest-rank percentile of the warp/weft stretch, and the largest stretch with
// the springs within two rows and two columns of a pin left out.
#include <gtest/gtest.h>

#include <cmath>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

// A rows x cols unit grid laid out again with column gaps `gaps` (every row the same) and unit
// row gaps: the weft spring from column c has length gaps[c] in every row, the warp springs
// length 1.
std::vector<double> with_column_gaps(uint32_t rows, const std::vector<double>& gaps) {
  const std::size_t cols = gaps.size() + 1;
  std::vector<double> x;
  for (uint32_t r = 0; r < rows; ++r) {
    double along = 0.0;
    for (std::size_t c = 0; c < cols; ++c) {
      x.insert(x.end(), {along, -static_cast<double>(r), 0.0});
      if (c + 1 < cols) along += gaps[c];
    }
  }
  return x;
}

TEST(RobustStretch, PercentileIsTheNearestRankOfTheWarpAndWeftRatios) {
  // 10 rows x 11 columns: 99 warp springs at 1 and, per column gap c = 0..9, 10 weft springs at
  // 1 + 0.01 (c + 1). Sorted: 99 x 1, 10 x 1.01, ..., 10 x 1.10 (199 springs).
  Scene scene = testing::bare_scene(10, 11);
  std::vector<double> gaps;
  for (int c = 0; c < 10; ++c) gaps.push_back(1.0 + 0.01 * (c + 1));
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    Cloth cloth(scene, precision, {});
    cloth.set_state(with_column_gaps(10, gaps), std::vector<double>(3 * 110, 0.0));
    const double tolerance = precision == Precision::Float32 ? 1e-6 : 1e-12;
    const auto percentile = [&](double fraction) {
      return cloth.stretch_percentile(Cloth::Springs::Structural, fraction);
    };
    EXPECT_NEAR(percentile(0.99), 1.10, tolerance);  // rank ceil(197.01) = 198: 190..199
    EXPECT_NEAR(percentile(0.94), 1.09, tolerance);  // rank ceil(187.06) = 188: 180..189
    EXPECT_NEAR(percentile(0.5), 1.01, tolerance);   // rank ceil(99.5) = 100: 100..109
    EXPECT_NEAR(percentile(0.4), 1.0, tolerance);    // rank ceil(79.6) = 80
    EXPECT_NEAR(percentile(1.0), cloth.stretch(Cloth::Springs::Structural).max, tolerance);
    // No pin: nothing is left out.
    EXPECT_EQ(cloth.stretch(Cloth::Springs::Structural).max_away_from_pins,
              cloth.stretch(Cloth::Springs::Structural).max);
  }
}

TEST(RobustStretch, PercentileLooksPastAFewOutliers) {
  // 20 rows x 11 columns at rest (409 warp/weft springs) but for particle (0, 10), the end of
  // the top row, pulled 2 m along the row: its weft spring at 3 x rest, its warp spring at
  // sqrt(5). The maximum sees them; the 99th percentile (the ceil(404.91) = 405th smallest)
  // does not.
  Scene scene = testing::bare_scene(20, 11);
  Cloth cloth(scene, Precision::Float64, {});
  std::vector<double> x;
  cloth.positions(x);
  x[3 * 10] += 2.0;
  cloth.set_state(x, std::vector<double>(3 * 220, 0.0));
  EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).max, 3.0, 1e-12);
  EXPECT_NEAR(cloth.stretch_percentile(Cloth::Springs::Structural, 0.99), 1.0, 1e-12);
  // The two largest are the top ranks: 408 of 409 is the warp spring.
  EXPECT_NEAR(cloth.stretch_percentile(Cloth::Springs::Structural, 408.0 / 409.0), std::sqrt(5.0),
              1e-12);
  EXPECT_THROW(cloth.stretch_percentile(Cloth::Springs::Structural, 0.0), std::invalid_argument);
  EXPECT_THROW(cloth.stretch_percentile(Cloth::Springs::Structural, 1.5), std::invalid_argument);
}

// Particle (row, col) of an 8 x 8 unit grid pinned at (0, 0) moved 0.3 along the columns: its
// left weft spring at 1.3, its right one at 0.7, its warp springs at sqrt(1.09).
Cloth::Stretch stretch_with_moved_particle(uint32_t row, uint32_t col, Precision precision) {
  Scene scene = testing::bare_scene(8, 8);
  scene.pinned = {0};
  Cloth cloth(scene, precision, {});
  std::vector<double> x;
  cloth.positions(x);
  x[3 * (row * 8 + col)] += 0.3;
  cloth.set_state(x, std::vector<double>(3 * 64, 0.0));
  return cloth.stretch(Cloth::Springs::Structural);
}

TEST(RobustStretch, MaxAwayFromPinsLeavesOutSpringsWithinTwoSpacingsOfAPin) {
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    const double tolerance = precision == Precision::Float32 ? 1e-6 : 1e-12;
    // (2, 4): the 1.3 spring runs from (2, 3), three columns from the pin: counted.
    const Cloth::Stretch far = stretch_with_moved_particle(2, 4, precision);
    EXPECT_NEAR(far.max, 1.3, tolerance);
    EXPECT_NEAR(far.max_away_from_pins, 1.3, tolerance);
    // (2, 3): the 1.3 spring starts at (2, 2), two rows and two columns from the pin: left
    // out; the warp springs at (2, 3) are not, and are the largest left.
    const Cloth::Stretch edge = stretch_with_moved_particle(2, 3, precision);
    EXPECT_NEAR(edge.max, 1.3, tolerance);
    EXPECT_NEAR(edge.max_away_from_pins, std::sqrt(1.09), tolerance);
    // (1, 1): every spring at it is near the pin; the rest are at rest.
    const Cloth::Stretch near = stretch_with_moved_particle(1, 1, precision);
    EXPECT_NEAR(near.max, 1.3, tolerance);
    EXPECT_NEAR(near.max_away_from_pins, 1.0, tolerance);
  }
}

TEST(RobustStretch, APinnedColumnLeavesOutTheThreeColumnsAtIt) {
  // The flag's pole: column 0 pinned on a 6 x 6 grid. Weft gaps 1.5, 1.4, 1.3, 1.2, 1.1: the
  // springs from columns 0..2 have an end within two columns of the pole; the largest left is
  // the one from column 3 (1.2). Threads do not change it (the 120 x 120 cloth below).
  Scene scene = testing::bare_scene(6, 6);
  for (uint32_t r = 0; r < 6; ++r) scene.pinned.push_back(r * 6);
  Cloth cloth(scene, Precision::Float64, {});
  cloth.set_state(with_column_gaps(6, {1.5, 1.4, 1.3, 1.2, 1.1}), std::vector<double>(108, 0.0));
  EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).max, 1.5, 1e-12);
  EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).max_away_from_pins, 1.2, 1e-12);

  Scene large = testing::bare_scene(120, 120);
  for (uint32_t r = 0; r < 120; ++r) large.pinned.push_back(r * 120);
  std::vector<double> gaps(119, 1.01);
  gaps[2] = 1.5;  // from column 2: left out
  gaps[3] = 1.2;  // from column 3: counted
  PipelineOptions threaded;
  threaded.threads = 2;
  for (const PipelineOptions& options : {PipelineOptions{}, threaded}) {
    Cloth cloth(large, Precision::Float64, options);
    cloth.set_state(with_column_gaps(120, gaps), std::vector<double>(3 * 120 * 120, 0.0));
    EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).max_away_from_pins, 1.2, 1e-12);
    EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).max, 1.5, 1e-12);
  }
}

}  // namespace
}  // namespace clothlab
