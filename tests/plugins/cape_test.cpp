// The cape scenario's script through clothlab.attachments/1: the targets' velocities are the
// derivatives of their positions, the speeds and the turn are the parameters', the script
// starts where the described cape hangs and runs on across its loops without a jump.
#include <clothlab/ext/attachments.h>
#include <gtest/gtest.h>

#include <array>
#include <clothlab/host/plugin_library.hpp>
#include <cmath>
#include <string>
#include <vector>

namespace clothlab::test {
namespace {

class Cape : public testing::Test {
 protected:
  Cape()
      : library_(host::PluginLibrary::load(CLOTHLAB_TEST_CAPE_PLUGIN)),
        instance_(library_.scenario().create(library_.scenario().default_params())),
        table_(static_cast<const clothlab_attachments_extension*>(
            library_.scenario().extension(CLOTHLAB_EXT_ATTACHMENTS))) {}

  // Positions then velocities, 3 per attached particle.
  std::array<std::vector<double>, 2> targets(double t) const {
    const uint32_t count = table_->count(instance_.get());
    std::array<std::vector<double>, 2> out{std::vector<double>(3 * count),
                                           std::vector<double>(3 * count)};
    clothlab_message message{};
    EXPECT_EQ(table_->targets(instance_.get(), t, out[0].data(), out[1].data(), &message),
              CLOTHLAB_OK)
        << message.text;
    return out;
  }

  host::PluginLibrary library_;
  host::ScenarioInstance instance_;
  const clothlab_attachments_extension* table_;
};

TEST_F(Cape, AttachesItsTopRow) {
  ASSERT_NE(table_, nullptr);
  const clothlab_scene scene = instance_.describe();
  std::vector<uint32_t> particles(table_->count(instance_.get()));
  clothlab_message message{};
  ASSERT_EQ(table_->particles(instance_.get(), particles.data(), &message), CLOTHLAB_OK);
  ASSERT_EQ(particles.size(), scene.cols);
  for (uint32_t col = 0; col < scene.cols; ++col) EXPECT_EQ(particles[col], col);
}

TEST_F(Cape, StartsWhereTheDescribedCapeHangs) {
  const clothlab_scene scene = instance_.describe();
  const auto [x, v] = targets(0.0);
  const double spacing = scene.width / (scene.cols - 1);
  for (uint32_t col = 0; col < scene.cols; ++col)
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(x[3 * col + axis], scene.origin[axis] + col * spacing * scene.col_axis[axis],
                  1e-12);
      EXPECT_EQ(v[3 * col + axis], 0.0);
    }
}

// Central differences away from the script's segment ends (0.5, 2, 3, 4, 6, 7, 8 s and a loop
// later), where the turn rate switches and the targets' velocities have a corner.
TEST_F(Cape, TargetVelocitiesAreTheDerivativesOfTheirPositions) {
  const double h = 1e-5;
  for (double t = 0.13; t < 16.0; t += 0.25) {
    const std::vector<double> x_before = targets(t - h)[0], x_after = targets(t + h)[0];
    const auto [x, v] = targets(t);
    for (std::size_t i = 0; i < x.size(); ++i)
      EXPECT_NEAR((x_after[i] - x_before[i]) / (2 * h), v[i], 1e-6) << "t = " << t << ", " << i;
  }
}

// Walking along +x at 1.5 m/s, then (after the 90 degree left turn) running along -z at 5 m/s,
// then standing; the shoulders move with the body.
TEST_F(Cape, WalksTurnsRunsAndStopsAtTheParametersSpeeds) {
  const std::pair<double, std::array<double, 3>> phases[] = {
      {1.0, {1.5, 0.0, 0.0}}, {5.0, {0.0, 0.0, -5.0}}, {7.5, {0.0, 0.0, 0.0}}};
  for (const auto& [t, expected] : phases) {
    const std::vector<double> v = targets(t)[1];
    for (std::size_t i = 0; i < v.size(); ++i)
      EXPECT_NEAR(v[i], expected[i % 3], 1e-12) << "t = " << t << ", " << i;
  }
}

TEST_F(Cape, RunsOnAcrossTheLoopWithoutAJump) {
  const auto [x_before, v_before] = targets(8.0 - 1e-9);
  const auto [x_after, v_after] = targets(8.0 + 1e-9);
  for (std::size_t i = 0; i < x_before.size(); ++i) {
    EXPECT_NEAR(x_before[i], x_after[i], 1e-8);
    EXPECT_NEAR(v_before[i], v_after[i], 1e-6);
  }
  // The second loop starts facing the first's end (a quarter turn left): it walks along -z.
  const std::vector<double> v = targets(9.0)[1];
  for (std::size_t i = 0; i < v.size(); ++i)
    EXPECT_NEAR(v[i], (std::array{0.0, 0.0, -1.5})[i % 3], 1e-12);
}

// The straight segments may last 0 s (configs/choose-cape-*.yaml compress the loop so): the
// targets stay finite through them (they were NaN: 0 / 0 in the straight walk's distance).
TEST_F(Cape, StraightSegmentsOfNoDurationKeepTheTargetsFinite) {
  host::ParamSet params = library_.scenario().default_params();
  for (const char* key : {"walk.duration", "run.duration"}) params.set(key, "0", "test");
  const host::ScenarioInstance compressed = library_.scenario().create(params);
  const uint32_t count = table_->count(compressed.get());
  std::vector<double> x(3 * count), v(3 * count);
  // Start 0.5 s, turn 1 s, speed-up 1 s, stop 1 s: the zero-length segments at 0.5 and 2.5 s.
  for (const double t : {0.5, 0.50001, 2.5, 2.50001, 3.2}) {
    clothlab_message message{};
    ASSERT_EQ(table_->targets(compressed.get(), t, x.data(), v.data(), &message), CLOTHLAB_OK)
        << message.text;
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_TRUE(std::isfinite(x[i])) << "t = " << t << ", " << i;
      EXPECT_TRUE(std::isfinite(v[i])) << "t = " << t << ", " << i;
    }
  }
}

}  // namespace
}  // namespace clothlab::test
