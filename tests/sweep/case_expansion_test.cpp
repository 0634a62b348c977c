#include <gtest/gtest.h>

#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "run_config.hpp"
#include "sweep_file.hpp"

namespace clothlab::sweep {
namespace {

using cli::parse_sweep;

SweepSpec two_by_three() {
  return parse_sweep(R"(steps: 100
precision: float64
sweep:
  name: grid
  matrix:
    integrator: [euler, rk4]
    mesh: [4x6, 8]
    dt: [0.001, 5e-3, 0.01]
)",
                     "grid.yaml");
}

TEST(CaseExpansion, EveryCombinationFirstAxisOutermost) {
  const auto cases = expand_cases(two_by_three());
  ASSERT_EQ(cases.size(), 12u);
  EXPECT_EQ(cases[0].key, "integrator=euler;mesh=4x6;dt=0.001");
  EXPECT_EQ(cases[1].key, "integrator=euler;mesh=4x6;dt=0.005");
  EXPECT_EQ(cases[3].key, "integrator=euler;mesh=8;dt=0.001");
  EXPECT_EQ(cases[11].key, "integrator=rk4;mesh=8;dt=0.01");
  EXPECT_EQ(cases[11].index, 11u);
  EXPECT_EQ(cases[4].integrator, "euler");
  EXPECT_DOUBLE_EQ(cases[1].dt, 0.005);
  EXPECT_EQ(cases[1].steps, 100u);
  EXPECT_EQ(cases[1].precision, "float64");
  EXPECT_EQ(cases[1].setting("mesh"), "4x6");
  // The key table reads the mesh: rows and cols reach the scenario.
  const std::vector<Setting> scenario = cli::resolve_run_config(cases[1].settings).scenario_params;
  ASSERT_EQ(scenario.size(), 2u);
  EXPECT_EQ(scenario[0].key + "=" + scenario[0].value, "rows=4");
  EXPECT_EQ(scenario[1].key + "=" + scenario[1].value, "cols=6");
  EXPECT_EQ(cases[1].setting("integrator.plugin"), "euler");
}

TEST(CaseExpansion, KeysDoNotDependOnNumberSpelling) {
  const auto a = expand_cases(parse_sweep(
      "duration: 1\nsweep: {name: a, matrix: {integrator: [rk4], dt: [0.0010]}}\n", "a.yaml"));
  const auto b = expand_cases(parse_sweep(
      "duration: 1\nsweep: {name: b, matrix: {integrator: [rk4], dt: [1e-3]}}\n", "b.yaml"));
  EXPECT_EQ(a[0].key, b[0].key);
}

TEST(CaseExpansion, WithDtReplacesTheAxisAndKey) {
  const auto cases = expand_cases(two_by_three());
  const CaseSpec changed = with_dt(cases[0], 0.02);
  EXPECT_EQ(changed.key, "integrator=euler;mesh=4x6;dt=0.02");
  EXPECT_DOUBLE_EQ(changed.dt, 0.02);
  EXPECT_EQ(changed.setting("dt"), "0.02");
  const CaseSpec quiet = with_setting(cases[0], "steps", "7", false);
  EXPECT_EQ(quiet.key, cases[0].key);
  EXPECT_EQ(quiet.steps, 7u);
}

}  // namespace
}  // namespace clothlab::sweep
