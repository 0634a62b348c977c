// Cloth::copy_raw_state / set_raw_state, the copy FrameWriter takes in the step loop: a raw
// state read back into a second cloth of the same scene gives the same state, bit for bit,
// and a cloth of another size refuses it.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

class RawState : public ::testing::TestWithParam<Precision> {};
INSTANTIATE_TEST_SUITE_P(Precisions, RawState,
                         ::testing::Values(Precision::Float32, Precision::Float64),
                         [](const ::testing::TestParamInfo<Precision>& info) {
                           return std::string(to_string(info.param));
                         });

TEST_P(RawState, RoundTripsIntoAnotherClothOfTheSameScene) {
  const Scene scene = testing::busy_scene(7, 5);
  Cloth source(scene, GetParam(), {});
  std::vector<double> x, v;
  source.positions(x);
  source.velocities(v);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] += 0.01 * static_cast<double>(i % 7);
    v[i] = 0.5 - 0.03 * static_cast<double>(i % 11);
  }
  source.set_state(x, v);

  Cloth::RawState state;
  source.copy_raw_state(state);
  Cloth target(scene, GetParam(), {true, 1});
  target.set_raw_state(state);

  std::vector<double> x_source, v_source, x_target, v_target;
  source.positions(x_source);
  source.velocities(v_source);
  target.positions(x_target);
  target.velocities(v_target);
  EXPECT_EQ(x_target, x_source);
  EXPECT_EQ(v_target, v_source);
  // Not the initial layout: the state really travelled.
  std::vector<double> x_initial;
  Cloth(scene, GetParam(), {}).positions(x_initial);
  EXPECT_NE(x_target, x_initial);
  EXPECT_DOUBLE_EQ(target.energy().total(), source.energy().total());
}

TEST_P(RawState, AClothOfAnotherSizeRefusesIt) {
  Cloth small(testing::busy_scene(4, 4), GetParam(), {});
  Cloth large(testing::busy_scene(40, 40), GetParam(), {});
  Cloth::RawState state;
  small.copy_raw_state(state);
  EXPECT_THROW(large.set_raw_state(state), std::invalid_argument);
}

TEST(RawStatePrecision, AFloat32StateDoesNotFitAFloat64Cloth) {
  const Scene scene = testing::busy_scene(20, 20);
  Cloth single(scene, Precision::Float32, {});
  Cloth twice(scene, Precision::Float64, {});
  Cloth::RawState state;
  single.copy_raw_state(state);
  EXPECT_THROW(twice.set_raw_state(state), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab
