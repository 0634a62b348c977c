#include "clothlab/sweep/stability_search.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "sweep_file.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using testing::ScratchFolder;

SweepSpec search_spec() {
  return cli::parse_sweep(R"(duration: 1
dt: 0.001
find_max_dt: {dt_min: 1e-6, dt_max: 0.5, tolerance: 0.01, growth: 1.5}
sweep:
  name: st
  mode: stability
  matrix: {integrator: [euler, rk4], mesh: [10]}
)",
                          "st.yaml");
}

double limit_of(const CaseSpec& c) { return c.integrator == "euler" ? 0.0042 : 0.011; }

CaseResult probe(const CaseSpec& c) {
  CaseResult result;
  if (c.dt > limit_of(c)) {
    result.status = CaseStatus::Unstable;
    result.check = "energy";
    result.reason = "energy at dt " + std::to_string(c.dt);
  }
  return result;
}

TEST(StabilitySearch, FindsTheLimitAndSetsItBesideThePrediction) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "st", false);
  const SweepSpec spec = search_spec();
  const auto predictor = [](const CaseSpec& c) {
    if (c.integrator == "rk4") throw std::runtime_error("no spectrum");
    return DtPrediction{limit_of(c) * 1.25, 300.0, {-10.0, 290.0}};
  };
  const auto summary =
      run_stability_search(spec, expand_cases(spec), probe, predictor, store, nullptr);
  EXPECT_EQ(summary.searched, 2u);
  const std::vector<Row> rows = store.rows();
  ASSERT_EQ(rows.size(), 2u);
  for (const Row& row : rows) {
    const double limit = row["integrator"] == "euler" ? 0.0042 : 0.011;
    EXPECT_EQ(row["outcome"], "bracketed");
    EXPECT_LE(row["dt_max"].get<double>(), limit);
    EXPECT_GT(row["dt_unstable"].get<double>(), limit);
    EXPECT_LE(row["dt_unstable"].get<double>() - row["dt_max"].get<double>(),
              0.01 * row["dt_max"].get<double>());
    EXPECT_EQ(row["check"], "energy");
  }
  const Row& euler = rows[0];
  EXPECT_NEAR(euler["measured_over_predicted"].get<double>(), 1.0 / 1.25, 0.01);
  EXPECT_DOUBLE_EQ(euler["omega_max"].get<double>(), 300.0);
  const Row& rk4 = rows[1];
  EXPECT_EQ(rk4["prediction_error"], "no spectrum");
  EXPECT_TRUE(rk4["measured_over_predicted"].is_null());
}

TEST(StabilitySearch, AProbeThatThrowsCountsAsUnstableWithItsReason) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "st", false);
  const SweepSpec spec = search_spec();
  const auto throwing = [](const CaseSpec& c) -> CaseResult {
    if (c.dt > 0.002) throw std::runtime_error("NaN from plugin");
    return {};
  };
  run_stability_search(spec, expand_cases(spec), throwing, nullptr, store, nullptr);
  const Row row = store.rows().at(0);
  EXPECT_LE(row["dt_max"].get<double>(), 0.002);
  EXPECT_EQ(row["fail_status"], "failed");
  EXPECT_EQ(row["reason"], "NaN from plugin");
}

}  // namespace
}  // namespace clothlab::sweep
