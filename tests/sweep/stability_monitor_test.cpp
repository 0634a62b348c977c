#include "clothlab/analysis/stability_monitor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace clothlab::analysis {
namespace {

constexpr double kStiffness = 50.0, kMass = 0.2;  // the free particle carries kMass / 2

// Two particles, one above the other; the top one pinned: a single structural spring.
Scene hanging_spring() {
  Scene scene;
  scene.rows = 2;
  scene.cols = 1;
  scene.width = 1.0;
  scene.height = 0.5;
  scene.total_mass = kMass;
  scene.structural = {kStiffness, 0.0};
  scene.pinned = {0};
  return scene;
}

Scene windy_flag() {
  Scene scene;
  scene.rows = 6;
  scene.cols = 6;
  scene.width = 1.0;
  scene.height = 1.0;
  scene.col_axis = {1, 0, 0};
  scene.row_axis = {0, -1, 0};
  scene.total_mass = 1.0;
  scene.structural = {200.0, 1.0};
  scene.shear = {200.0, 1.0};
  scene.flexion = {50.0, 0.5};
  scene.wind_direction = {0, 0, 1};
  scene.wind_strength = 5.0;
  scene.pinned = {0, 6, 12, 18, 24, 30};
  return scene;
}

struct FreeDeleter {
  void operator()(double* p) const { std::free(p); }
};

// The seed's Euler (v += dt a; x += dt v), written here against the system table.
class SymplecticEulerLoop {
 public:
  explicit SymplecticEulerLoop(Cloth& cloth)
      : system_(cloth.system()),
        acceleration_(static_cast<double*>(
            std::aligned_alloc(64, 64 * ((3 * system_.stride * 8 + 63) / 64)))) {}

  void step(double t, double dt) {
    ASSERT_EQ(
        system_.eval_acceleration(system_.context, t, system_.x, system_.v, acceleration_.get()),
        CLOTHLAB_OK);
    system_.axpy(system_.context, system_.v, dt, acceleration_.get());
    system_.axpy(system_.context, system_.x, dt, system_.v);
  }

 private:
  const clothlab_system& system_;
  std::unique_ptr<double[], FreeDeleter> acceleration_;
};

Verdict run(Cloth& cloth, double dt, int steps, const MonitorOptions& options) {
  StabilityMonitor monitor(cloth, 0.0, options);
  SymplecticEulerLoop loop(cloth);
  for (int i = 1; i <= steps; ++i) {
    loop.step((i - 1) * dt, dt);
    if (!monitor.observe(cloth, static_cast<uint64_t>(i), i * dt).stable) break;
  }
  return monitor.check(cloth, static_cast<uint64_t>(steps), steps * dt);
}

double omega() { return std::sqrt(kStiffness / (kMass / 2.0)); }

TEST(StabilityMonitor, CalmSpringIsNotFlagged) {
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  const Verdict verdict = run(cloth, 0.1 / omega(), 2000, {});
  EXPECT_TRUE(verdict.stable) << verdict.reason;
  EXPECT_EQ(verdict.fired, StabilityCheck::None);
}

TEST(StabilityMonitor, TooLargeStepIsFlaggedEarly) {
  // Symplectic Euler needs w dt < 2; at 2.5 the amplitude grows about fourfold per step.
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  MonitorOptions options;
  options.check_interval = 1;
  const Verdict verdict = run(cloth, 2.5 / omega(), 2000, options);
  EXPECT_FALSE(verdict.stable);
  EXPECT_NE(verdict.fired, StabilityCheck::None);
  EXPECT_LT(verdict.step, 20u);
  EXPECT_FALSE(verdict.reason.empty());
}

TEST(StabilityMonitor, StretchCheckFiresBeyondTheLimit) {
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  MonitorOptions options;
  options.check_interval = 1;
  options.energy_margin = 1e12;  // leave the stretch check alone to fire
  options.stretch_limit = 2.0;
  const Verdict verdict = run(cloth, 2.5 / omega(), 2000, options);
  ASSERT_EQ(verdict.fired, StabilityCheck::Stretch) << verdict.reason;
  EXPECT_GT(verdict.value, 2.0);
  EXPECT_DOUBLE_EQ(verdict.limit, 2.0);
}

TEST(StabilityMonitor, EnergyCheckFiresWhenStretchIsAllowed) {
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  MonitorOptions options;
  options.check_interval = 1;
  options.stretch_limit = 1e12;
  const Verdict verdict = run(cloth, 2.5 / omega(), 2000, options);
  ASSERT_EQ(verdict.fired, StabilityCheck::Energy) << verdict.reason;
  EXPECT_GT(verdict.value, verdict.limit);
}

TEST(StabilityMonitor, NonFiniteStateIsFlagged) {
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  StabilityMonitor monitor(cloth, 0.0);
  std::vector<double> x, v;
  cloth.positions(x);
  cloth.velocities(v);
  v[4] = std::numeric_limits<double>::quiet_NaN();
  cloth.set_state(x, v);
  const Verdict& verdict = monitor.observe(cloth, 10, 0.1);
  EXPECT_EQ(verdict.fired, StabilityCheck::NonFinite);
  EXPECT_EQ(verdict.step, 10u);
}

TEST(StabilityMonitor, ChecksOnlyEveryInterval) {
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  MonitorOptions options;
  options.check_interval = 5;
  StabilityMonitor monitor(cloth, 0.0, options);
  for (uint64_t step = 1; step <= 20; ++step) monitor.observe(cloth, step, 0.01 * step);
  EXPECT_EQ(monitor.checks(), 4u);
}

TEST(StabilityMonitor, WindyFlagStaysWithinTheWindWorkBound) {
  Cloth cloth(windy_flag(), Precision::Float64, {});
  MonitorOptions options;
  options.check_interval = 1;
  const Verdict verdict = run(cloth, 5e-4, 4000, options);
  EXPECT_TRUE(verdict.stable) << verdict.reason;
}

// The drag and lift (clothlab.air/1) push a free cloth from rest: its energy grows, and the
// monitor's bound on the external forces' work covers it. Without gravity the energy margin is
// zero, so without the air's term in the bound the first check after the push would fail.
TEST(StabilityMonitor, AFreeClothPushedByTheAirStaysWithinTheWorkBound) {
  Scene scene = windy_flag();
  scene.wind_strength = 0.0;
  scene.pinned.clear();
  scene.gravity = {0, 0, 0};
  scene.row_axis = {0, 0.6, -0.8};  // tilted to the stream: drag and lift both act
  scene.air = {{12.0, 0.0, 5.0}, 1.225, 1.2, 1.0};
  Cloth cloth(scene, Precision::Float64, {});
  MonitorOptions options;
  options.check_interval = 1;
  const Verdict verdict = run(cloth, 5e-4, 2000, options);
  EXPECT_TRUE(verdict.stable) << verdict.reason;
  EXPECT_GT(cloth.energy().kinetic, 1.0);
}

// The hanging spring's top particle lifted at a steady 1 m/s for 20 s: the free particle rises
// 20 m, 19.6 J of gravitational energy, about 9 times the monitor's margin.
class SteadyLift final : public AttachmentSource {
 public:
  bool targets(double t, std::span<double> positions,
               std::span<double> velocities) noexcept override {
    positions[0] = positions[2] = velocities[0] = velocities[2] = 0.0;
    positions[1] = speed * t;
    velocities[1] = speed;
    return true;
  }
  static constexpr double speed = 1.0;
};

struct LiftedRun {
  Verdict verdict;
  double energy_gain = 0, attachment_work = 0;
};

// Symplectic Euler with the pin moved to its target after each step (as the built-ins do).
LiftedRun lift(double dt, double duration, double velocity_gain) {
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  SteadyLift source;
  const uint32_t top = 0;
  cloth.set_attachments({&top, 1}, source);
  EXPECT_TRUE(cloth.move_attachments(0.0));
  MonitorOptions options;
  options.check_interval = 1;
  options.stretch_limit = 1e12;  // the energy check alone
  StabilityMonitor monitor(cloth, 0.0, options);
  const double initial = cloth.energy().total();
  SymplecticEulerLoop loop(cloth);
  const int steps = static_cast<int>(std::lround(duration / dt));
  std::vector<double> x, v;
  for (int i = 1; i <= steps && monitor.verdict().stable; ++i) {
    loop.step((i - 1) * dt, dt);
    if (velocity_gain != 1.0) {  // the mutant: a little energy from nowhere every step
      cloth.positions(x);
      cloth.velocities(v);
      for (int axis = 0; axis < 3; ++axis) v[3 + axis] *= velocity_gain;
      cloth.set_state(x, v);
    }
    EXPECT_TRUE(cloth.move_attachments(i * dt));
    monitor.observe(cloth, static_cast<uint64_t>(i), i * dt);
  }
  return {monitor.verdict(), cloth.energy().total() - initial, monitor.attachment_work()};
}

TEST(StabilityMonitor, APinLiftingTheClothDoesWorkThatBalancesItsEnergyGain) {
  const LiftedRun run = lift(1e-3, 20.0, 1.0);
  EXPECT_TRUE(run.verdict.stable) << run.verdict.reason;
  // Undamped: the energy gained is the work the pin did, to the trapezoid rule's error.
  EXPECT_GT(run.energy_gain, 19.0);
  EXPECT_NEAR(run.attachment_work, run.energy_gain, 1e-3 * run.energy_gain);
}

TEST(StabilityMonitor, AnEnergyInjectingStepOnALiftedClothIsStillFlagged) {
  // 0.2 % more velocity per step: the mutant's energy grows without bound beyond the work.
  const LiftedRun run = lift(1e-3, 20.0, 1.002);
  EXPECT_FALSE(run.verdict.stable);
  EXPECT_EQ(run.verdict.fired, StabilityCheck::Energy) << run.verdict.reason;
  EXPECT_NE(run.verdict.reason.find("attachment work"), std::string::npos) << run.verdict.reason;
}

TEST(StabilityMonitor, RejectsOptionsOutOfRange) {
  Cloth cloth(hanging_spring(), Precision::Float64, {});
  MonitorOptions options;
  options.check_interval = 0;
  EXPECT_THROW(StabilityMonitor(cloth, 0.0, options), std::invalid_argument);
  options = {};
  options.stretch_limit = 0.5;
  EXPECT_THROW(StabilityMonitor(cloth, 0.0, options), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab::analysis
