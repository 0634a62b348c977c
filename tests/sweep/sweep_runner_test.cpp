#include "clothlab/sweep/sweep_runner.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>

#include "sweep_file.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using cli::parse_sweep;

using testing::ScratchFolder;

std::vector<CaseSpec> six_cases() {
  return expand_cases(parse_sweep(R"(duration: 1
sweep:
  name: six
  matrix: {integrator: [euler, rk4], dt: [0.001, 0.01, 0.02]}
)",
                                  "six.yaml"));
}

// Fake physics: stable below dt 0.015; rk4 at 0.001 throws.
CaseResult fake_run(const CaseSpec& c) {
  if (c.integrator == "rk4" && c.dt == 0.001) throw std::runtime_error("plugin exploded");
  CaseResult result;
  if (c.dt > 0.015) {
    result.status = CaseStatus::Unstable;
    result.fail_step = 42;
    result.check = "stretch";
    result.reason = "spring stretched";
  }
  result.metrics = {{"ms_per_step", 0.5}};
  return result;
}

TEST(SweepRunner, DivergenceAndExceptionsAreResultsNotAborts) {
  ScratchFolder scratch;
  ResultsStore store(scratch.path() / "results", false);
  const SweepSummary summary = run_sweep(six_cases(), fake_run, store, nullptr);
  EXPECT_EQ(summary.total, 6u);
  EXPECT_EQ(summary.stable, 3u);
  EXPECT_EQ(summary.unstable, 2u);
  EXPECT_EQ(summary.failed, 1u);
  const std::vector<Row> rows = store.rows();
  ASSERT_EQ(rows.size(), 6u);
  const Row& failed = rows[3];
  EXPECT_EQ(failed["key"], "integrator=rk4;dt=0.001");
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_EQ(failed["reason"], "plugin exploded");
  const Row& unstable = rows[2];
  EXPECT_EQ(unstable["stable"], false);
  EXPECT_EQ(unstable["fail_step"], 42);
  EXPECT_EQ(unstable["check"], "stretch");
  EXPECT_EQ(rows[0]["ms_per_step"], 0.5);
  EXPECT_EQ(rows[0]["integrator"], "euler");
}

TEST(SweepRunner, StoreHoldsEveryFinishedCaseAndResumeSkipsDoneCases) {
  ScratchFolder scratch;
  const auto cases = six_cases();
  std::size_t calls = 0;
  auto observing_run = [&](const CaseSpec& c) {
    // Before each case, the store on disk holds exactly the cases finished so far.
    EXPECT_EQ(read_results(scratch.path() / "results.sqlite").rows.size(), calls);
    ++calls;
    CaseResult result;
    result.metrics = {{"dt_seen", c.dt}};
    return result;
  };
  {  // An interrupted sweep: only the first four cases ran.
    ResultsStore store(scratch.path() / "results", false);
    run_sweep(std::vector<CaseSpec>(cases.begin(), cases.begin() + 4), observing_run, store,
              nullptr);
  }
  ResultsStore resumed(scratch.path() / "results", true);
  std::vector<std::string> ran;
  const SweepSummary summary = run_sweep(
      cases,
      [&](const CaseSpec& c) {
        ran.push_back(c.key);
        return observing_run(c);
      },
      resumed, nullptr);
  EXPECT_EQ(summary.skipped, 4u);
  EXPECT_EQ(ran, (std::vector<std::string>{cases[4].key, cases[5].key}));
  EXPECT_EQ(resumed.rows().size(), 6u);
}

TEST(SweepRunner, ProgressLineShowsCountsElapsedAndEta) {
  EXPECT_EQ(Progress::format_line(3, 12, 30.0, 3, "rk4 dt=0.001"),
            "[3/12]  25.0%  elapsed 0:30  ETA 1:30  rk4 dt=0.001");
  EXPECT_EQ(Progress::format_duration(3725.0), "1:02:05");
  std::ostringstream out;
  Progress progress(2, 0, out, true);
  progress.case_finished("a");
  progress.finish();
  EXPECT_EQ(out.str().substr(0, 7), "\r[1/2] ");
  EXPECT_EQ(out.str().back(), '\n');
  std::ostringstream silent;
  Progress quiet(2, 0, silent, false);
  quiet.case_finished("a");
  quiet.finish();
  EXPECT_TRUE(silent.str().empty());
}

}  // namespace
}  // namespace clothlab::sweep
