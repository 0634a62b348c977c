// The session stepped by its caller (host/session/simulation.hpp): steps taken in pieces are
// the run's steps, the run ends where it ends, and record() after the last step is run()'s.
#include <gtest/gtest.h>

#include <clothlab/host/errors.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <vector>

#include "run_config.hpp"
#include "simulation.hpp"

namespace {

using clothlab::cli::RunConfig;
using clothlab::cli::Setting;
using clothlab::cli::Simulation;

const clothlab::host::PluginSearchPath& builtin_plugins() {
  static const clothlab::host::PluginSearchPath path({CLOTHLAB_BUILTIN_PLUGIN_DIR});
  return path;
}

RunConfig flag_config(const char* integrator, const char* dt) {
  return clothlab::cli::resolve_run_config({{"integrator.plugin", integrator, "test"},
                                            {"scenario.plugin", "flag", "test"},
                                            {"scenario.rows", "10", "test"},
                                            {"scenario.cols", "10", "test"},
                                            {"dt", dt, "test"},
                                            {"steps", "100", "test"},
                                            {"precision", "float64", "test"},
                                            {"threads", "1", "test"}});
}

std::vector<double> positions(const Simulation& simulation) {
  std::vector<double> x;
  simulation.cloth().positions(x);
  return x;
}

TEST(Session, StepsInPiecesAreTheRunsSteps) {
  const RunConfig config = flag_config("verlet", "0.0005");
  Simulation whole(config, builtin_plugins());
  const clothlab::cli::RunRecord expected = whole.run({nullptr, nullptr, true});

  Simulation pieces(config, builtin_plugins());
  const clothlab::cli::RunHooks hooks{nullptr, nullptr, true};
  EXPECT_EQ(pieces.step(7, hooks), 7u);
  EXPECT_DOUBLE_EQ(pieces.time(), 7 * config.dt);
  EXPECT_EQ(pieces.advance(13 * config.dt, hooks), 13u);
  EXPECT_EQ(pieces.steps_left(), 80u);
  EXPECT_EQ(pieces.step(1000, hooks), 80u);  // no further than the run's end
  EXPECT_TRUE(pieces.finished());
  EXPECT_EQ(pieces.step(5, hooks), 0u);

  EXPECT_EQ(positions(pieces), positions(whole));
  const clothlab::cli::RunRecord record = pieces.record();
  EXPECT_EQ(record.verdict, expected.verdict);
  EXPECT_EQ(record.steps_taken, expected.steps_taken);
  EXPECT_EQ(record.stability_checks, expected.stability_checks);
  EXPECT_EQ(record.max_stretch_over_run, expected.max_stretch_over_run);
  EXPECT_EQ(record.final_p99_stretch, expected.final_p99_stretch);
  ASSERT_EQ(record.energy_trace.size(), expected.energy_trace.size());
  EXPECT_EQ(record.energy_trace.back().energy.total(), expected.energy_trace.back().energy.total());
}

TEST(Session, AFailedCheckEndsTheRunWhereItFailed) {
  Simulation simulation(flag_config("euler", "0.01"), builtin_plugins());
  const uint64_t taken = simulation.step(100);
  EXPECT_LT(taken, 100u);
  EXPECT_FALSE(simulation.stable());
  EXPECT_TRUE(simulation.finished());
  EXPECT_EQ(simulation.steps_left(), 0u);
  const clothlab::cli::RunRecord record = simulation.record();
  EXPECT_FALSE(record.stable);
  EXPECT_FALSE(record.failed_check.empty());
  EXPECT_EQ(record.failed_step, taken);
}

TEST(Session, AdvanceRefusesATimeThatIsNotOne) {
  Simulation simulation(flag_config("verlet", "0.0005"), builtin_plugins());
  EXPECT_THROW(simulation.advance(-1), clothlab::host::InputError);
  EXPECT_EQ(simulation.advance(0), 0u);
  EXPECT_EQ(simulation.steps_taken(), 0u);
}

TEST(Session, AWrittenStateIsWhereTheNextStepStarts) {
  const RunConfig config = flag_config("verlet", "0.0005");
  Simulation pushed(config, builtin_plugins());
  Simulation control(config, builtin_plugins());
  pushed.step(20);
  control.step(20);
  std::vector<double> x, v;
  pushed.cloth().positions(x);
  pushed.cloth().velocities(v);
  for (size_t i = 2; i < v.size(); i += 3) v[i] += 0.5;
  pushed.cloth().set_state(x, v);
  pushed.state_written();
  pushed.step(1);
  control.step(1);
  EXPECT_NE(positions(pushed), positions(control));
}

}  // namespace
