// The SIMD targets (docs/reference/simd-dispatch.md): each target this build contains and this
// CPU runs, forced in turn through CLOTHLAB_SIMD, agrees with the float64 reference to float32's
// tolerance and gives the same bits on one and two threads; a target that cannot run here is a
// one-line error naming the CPU's features and the targets built.
#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/core/simd.hpp>
#include <clothlab/sdk/simd_target.hpp>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>

#include "cloth_test_support.hpp"
#include "reference_forces.hpp"

namespace clothlab {
namespace {

using testing::busy_scene;

// Sets CLOTHLAB_SIMD for its lifetime; restores the value it found.
class ForcedTarget {
 public:
  explicit ForcedTarget(const std::string& target) {
    if (const char* before = std::getenv("CLOTHLAB_SIMD")) before_ = before;
    setenv("CLOTHLAB_SIMD", target.c_str(), 1);
  }
  ~ForcedTarget() {
    if (before_) {
      setenv("CLOTHLAB_SIMD", before_->c_str(), 1);
    } else {
      unsetenv("CLOTHLAB_SIMD");
    }
  }
  ForcedTarget(const ForcedTarget&) = delete;
  ForcedTarget& operator=(const ForcedTarget&) = delete;

 private:
  std::optional<std::string> before_;
};

std::vector<std::string> runnable_targets() {
  std::vector<std::string> targets;
  for (std::string_view target : simd_targets_built())
    if (sdk::cpu_runs_simd_target(target)) targets.emplace_back(target);
  return targets;
}

// Positions jittered by up to a fifth of a cell and velocities everywhere, so every spring and
// damper pulls.
void disturb(Cloth& cloth, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  std::vector<double> x, v;
  cloth.positions(x);
  v.resize(x.size());
  for (double& component : x) component += jitter(random);
  for (double& component : v) component = 20 * jitter(random);
  cloth.set_state(x, v);
}

// Each target's float32 acceleration of the cloth, brought to its state by `prepare`, against
// the float64 reference's at the same (float-rounded) state.
template <class Prepare>
void expect_each_target_agrees(const Scene& scene, Prepare prepare) {
  const std::vector<std::string> targets = runnable_targets();
  ASSERT_FALSE(targets.empty());
  for (const std::string& target : targets) {
    SCOPED_TRACE(target);
    const ForcedTarget forced(target);
    EXPECT_EQ(simd_target(), target);
    Cloth cloth(scene, Precision::Float32, {});
    prepare(cloth);
    std::vector<double> x, v;
    cloth.positions(x);  // rounded to float: exactly what the kernels see
    cloth.velocities(v);
    const std::vector<double> fast = testing::acceleration<float>(cloth);
    reference::ReferenceCloth<double> reference(scene);
    std::vector<double> exact(x.size());
    reference.acceleration(x.data(), v.data(), exact.data());
    double scale = 0.0;
    for (double component : exact) scale = std::max(scale, std::abs(component));
    ASSERT_GT(scale, 0.0);
    for (std::size_t e = 0; e < exact.size(); ++e)
      ASSERT_NEAR(fast[e], exact[e], 2e-5 * scale)
          << "particle " << e / 3 << " component " << e % 3;
  }
}

TEST(SimdTargets, EachAgreesWithTheFloat64Reference) {
  // Interior rows, tails of every lane width.
  expect_each_target_agrees(busy_scene(37, 53), [](Cloth& cloth) { disturb(cloth, 7); });
}

// Two neighbours of an interior row at one point: a spring of zero length, which pulls
// neither end, and a cell triangle of zero area, which the wind does not push; the kernels'
// inverse square root of 0 must stay finite (inverse_sqrt.hpp).
TEST(SimdTargets, EachAgreesWithTheFloat64ReferenceWhereTwoParticlesMeet) {
  const Scene scene = busy_scene(37, 53);
  expect_each_target_agrees(scene, [&](Cloth& cloth) {
    disturb(cloth, 7);
    std::vector<double> x, v;
    cloth.positions(x);
    cloth.velocities(v);
    const std::size_t particle = 10 * std::size_t{scene.cols} + 20;  // clear of every block edge
    for (std::size_t k = 0; k < 3; ++k) x[3 * (particle + 1) + k] = x[3 * particle + k];
    cloth.set_state(x, v);
  });
}

TEST(SimdTargets, EachGivesTheSameBitsOnOneAndTwoThreads) {
  const Scene scene = busy_scene(80, 70);  // large enough to run threaded
  PipelineOptions one, two;
  one.threads = 1;
  two.threads = 2;
  for (const std::string& target : runnable_targets()) {
    SCOPED_TRACE(target);
    const ForcedTarget forced(target);
    Cloth serial(scene, Precision::Float32, one);
    Cloth threaded(scene, Precision::Float32, two);
    disturb(serial, 11);
    disturb(threaded, 11);
    EXPECT_EQ(testing::acceleration<float>(serial), testing::acceleration<float>(threaded));
  }
}

TEST(SimdTargets, UnsetTakesTheWidestThatRuns) {
  const ForcedTarget forced("");
  EXPECT_EQ(simd_target(), runnable_targets().back());
}

TEST(SimdTargets, AnUnknownNameIsAOneLineError) {
  const ForcedTarget forced("sse9");
  try {
    Cloth cloth(busy_scene(4, 4), Precision::Float32, {});
    FAIL() << "CLOTHLAB_SIMD=sse9 made a cloth";
  } catch (const std::invalid_argument& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("CLOTHLAB_SIMD=sse9: unknown target"), std::string::npos) << text;
    EXPECT_NE(text.find("this CPU has: "), std::string::npos) << text;
    EXPECT_NE(text.find("targets built: " + std::string(simd_targets_built().front())),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find('\n'), std::string::npos) << text;
  }
}

TEST(SimdTargets, ATargetNotBuiltOrNotRunIsRefused) {
  const std::string_view portable_only[] = {"portable"};
  const sdk::SimdChoice not_built = sdk::choose_simd_target(portable_only, "avx2");
  EXPECT_TRUE(not_built.target.empty());
  EXPECT_NE(not_built.error.find("CLOTHLAB_SIMD=avx2: target not built into this build"),
            std::string::npos)
      << not_built.error;
  EXPECT_NE(not_built.error.find("targets built: portable)"), std::string::npos);

  const std::string_view all[] = {"portable", "avx2", "avx512"};
  for (std::string_view target : all) {
    const sdk::SimdChoice choice = sdk::choose_simd_target(all, std::string(target).c_str());
    if (sdk::cpu_runs_simd_target(target)) {
      EXPECT_EQ(choice.target, target);
    } else {
      EXPECT_NE(choice.error.find("this CPU lacks the target"), std::string::npos) << target;
    }
  }
  EXPECT_FALSE(sdk::cpu_runs_simd_target("avx1024"));
}

}  // namespace
}  // namespace clothlab
