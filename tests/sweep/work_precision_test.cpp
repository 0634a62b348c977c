#include "clothlab/sweep/work_precision.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "clothlab/sweep/shard.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "sweep_file.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using testing::read_text;
using testing::ScratchFolder;

constexpr double kDuration = 0.04, kDiagonal = 2.0;

SweepSpec ladder_spec() {
  return cli::parse_sweep(R"(duration: 0.04
work_precision: {reference_integrator: rk4, refinement: 16, dt_start: 0.01, levels: 5}
sweep:
  name: wp
  mode: work-precision
  matrix: {integrator: [euler, midpoint], scenario: [sheet]}
)",
                          "wp.yaml");
}

// Fake integrators with a known global error: x = exact + C dt^p along x of particle 0
// (exact x = 0 there, so even the reference's tiny error is representable).
// Euler at the coarsest step diverges.
struct FakeIntegrators {
  int calls = 0;
  Trajectory operator()(const CaseSpec& c) {
    ++calls;
    EXPECT_NEAR(static_cast<double>(c.steps) * c.dt, kDuration, 1e-12) << c.key;
    const int order = c.integrator == "euler" ? 1 : c.integrator == "midpoint" ? 2 : 4;
    Trajectory run;
    run.diagonal = kDiagonal;
    run.positions = {5.0 * std::pow(c.dt, order), 0.1, 0.0, 1.0, 0.2, -0.5};
    run.summary.wall_time_s = 1e-3 * static_cast<double>(c.steps);
    run.summary.force_evals = c.steps;
    if (c.integrator == "euler" && c.dt == 0.01) {
      run.verdict.status = CaseStatus::Unstable;
      run.verdict.reason = "energy";
    }
    return run;
  }
};

// Both cases need the same reference: each shard computes it, the merge keeps it once, where
// the unsharded run wrote it (before the first case's ladder).
TEST(WorkPrecision, MergedShardsExportTheSameFilesAsAnUnshardedRun) {
  ScratchFolder scratch;
  const SweepSpec spec = ladder_spec();
  const auto cases = expand_cases(spec);
  const auto run_into = [&](const std::filesystem::path& base, const std::vector<CaseSpec>& part) {
    ResultsStore store(base, false, {{"mode", "work-precision"}});
    FakeIntegrators fake;
    run_work_precision(
        spec, part, [&](const CaseSpec& c) { return fake(c); }, store, nullptr);
    store.mark_complete();
    store.write_exports();
  };
  run_into(scratch.path() / "whole" / "wp", cases);
  const auto base = scratch.path() / "sharded" / "wp";
  for (std::size_t k = 1; k <= 2; ++k)
    run_into(shard_base(base, {k, 2}), shard_cases(cases, {k, 2}));
  EXPECT_EQ(merge_shards(base).rows, 13u);  // 1 reference + 2 x (5 ladder rows + 1 fit)
  EXPECT_EQ(read_text(base.string() + ".csv"), read_text(scratch.path() / "whole" / "wp.csv"));
  EXPECT_EQ(read_text(base.string() + ".json"), read_text(scratch.path() / "whole" / "wp.json"));
}

TEST(WorkPrecision, RelativeRmsErrorIsOverParticlesAndDiagonal) {
  // Two particles, displaced by 3 and 4: RMS = sqrt((9 + 16) / 2).
  EXPECT_DOUBLE_EQ(relative_rms_error({3, 0, 0, 0, 4, 0}, {0, 0, 0, 0, 0, 0}, 2.0),
                   std::sqrt(12.5) / 2.0);
}

TEST(WorkPrecision, LaddersFitTheKnownOrdersAndReportTheReference) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "wp", false);
  FakeIntegrators fake;
  const SweepSpec spec = ladder_spec();
  const auto summary = run_work_precision(
      spec, expand_cases(spec), [&](const CaseSpec& c) { return fake(c); }, store, nullptr);
  EXPECT_EQ(summary.references, 1u);
  EXPECT_EQ(summary.runs, 10u);
  EXPECT_EQ(fake.calls, 12);

  const std::optional<Row> reference = store.find("work-precision;reference;scenario=sheet");
  ASSERT_TRUE(reference.has_value());
  const double h = 0.000625 / 16.0;
  const double difference = 5.0 * (std::pow(h, 4) - std::pow(h / 2.0, 4));
  EXPECT_NEAR((*reference)["reference_difference"].get<double>(),
              difference / std::sqrt(2.0) / kDiagonal, 1e-12 * difference);
  EXPECT_DOUBLE_EQ((*reference)["reference_dt"].get<double>(), h / 2.0);
  EXPECT_DOUBLE_EQ((*reference)["T"].get<double>(), kDuration);

  const std::optional<Row> diverged =
      store.find("work-precision;ladder;integrator=euler;scenario=sheet;dt=0.01");
  ASSERT_TRUE(diverged.has_value());
  EXPECT_TRUE((*diverged)["error"].is_null());
  EXPECT_EQ((*diverged)["status"], "unstable");

  const std::optional<Row> euler = store.find("work-precision;fit;integrator=euler;scenario=sheet");
  const std::optional<Row> midpoint =
      store.find("work-precision;fit;integrator=midpoint;scenario=sheet");
  ASSERT_TRUE(euler.has_value());
  ASSERT_TRUE(midpoint.has_value());
  EXPECT_NEAR((*euler)["order"].get<double>(), 1.0, 1e-3);
  EXPECT_EQ((*euler)["fit_points"], 4);  // the diverged step is not fitted
  EXPECT_NEAR((*midpoint)["order"].get<double>(), 2.0, 1e-3);
  EXPECT_DOUBLE_EQ((*midpoint)["fit_dt_max"].get<double>(), 0.01);
}

TEST(WorkPrecision, ResumeRunsNothingTwice) {
  ScratchFolder scratch;
  const SweepSpec spec = ladder_spec();
  FakeIntegrators fake;
  auto runner = [&](const CaseSpec& c) { return fake(c); };
  {
    ResultsStore store(scratch.path() / "wp", false);
    run_work_precision(spec, expand_cases(spec), runner, store, nullptr);
  }
  fake.calls = 0;
  ResultsStore resumed(scratch.path() / "wp", true);
  const auto summary = run_work_precision(spec, expand_cases(spec), runner, resumed, nullptr);
  EXPECT_EQ(fake.calls, 0);
  EXPECT_EQ(summary.skipped, 10u);
}

TEST(WorkPrecision, DurationThatIsNotWholeStepsIsRejected) {
  ScratchFolder scratch;
  SweepSpec spec = ladder_spec();
  spec.work_precision.dt_start = 0.003;  // 0.04 / 0.003 is not whole
  ResultsStore store(scratch.path() / "wp", false);
  FakeIntegrators fake;
  EXPECT_THROW(
      run_work_precision(
          spec, expand_cases(spec), [&](const CaseSpec& c) { return fake(c); }, store, nullptr),
      SweepError);
}

TEST(WorkPrecision, SelfReferencedIntegratorsGetTheirOwnReference) {
  ScratchFolder scratch;
  SweepSpec spec = ladder_spec();
  spec.work_precision.self_reference = {"midpoint"};
  ResultsStore store(scratch.path() / "wp", false);
  FakeIntegrators fake;
  const auto summary = run_work_precision(
      spec, expand_cases(spec), [&](const CaseSpec& c) { return fake(c); }, store, nullptr);
  EXPECT_EQ(summary.references, 2u);
  EXPECT_EQ(fake.calls, 14);
  const std::optional<Row> own =
      store.find("work-precision;reference;scenario=sheet;integrator=midpoint");
  ASSERT_TRUE(own.has_value());
  EXPECT_EQ((*own)["reference_integrator"], "midpoint");
  EXPECT_TRUE((*own)["reference_error_estimate"].is_null());
  // Against itself at dt_ref the error is 5 (dt^2 - dt_ref^2) / sqrt(2) / diagonal.
  const std::optional<Row> ladder =
      store.find("work-precision;ladder;integrator=midpoint;scenario=sheet;dt=0.01");
  ASSERT_TRUE(ladder.has_value());
  const double h = 0.000625 / 16.0 / 2.0;
  EXPECT_NEAR((*ladder)["error"].get<double>(), 5.0 * (1e-4 - h * h) / std::sqrt(2.0) / kDiagonal,
              1e-15);
}

}  // namespace
}  // namespace clothlab::sweep
