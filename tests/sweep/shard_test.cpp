#include "clothlab/sweep/shard.hpp"

#include <gtest/gtest.h>

#include "clothlab/sweep/results_store.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "clothlab/sweep/sweep_runner.hpp"
#include "sweep_file.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using cli::parse_sweep;

using testing::read_text;
using testing::ScratchFolder;

std::vector<CaseSpec> matrix_cases() {  // 3 x 4 x 2 = 24 cases
  return expand_cases(parse_sweep(R"(duration: 1
sweep:
  name: grid
  matrix: {integrator: [euler, midpoint, rk4], dt: [0.001, 0.002, 0.01, 0.02],
           precision: [float32, float64]}
)",
                                  "grid.yaml"));
}

// Deterministic fake physics, so that two runs of a case give the same row.
CaseResult fake_run(const CaseSpec& c) {
  CaseResult result;
  if (c.dt > 0.015 && c.integrator == "euler") {
    result.status = CaseStatus::Unstable;
    result.fail_step = 7;
    result.check = "stretch";
  }
  result.metrics = {{"steps", c.duration / c.dt}, {"index", static_cast<double>(c.index)}};
  return result;
}

void run_into(const std::filesystem::path& base, const std::vector<CaseSpec>& cases) {
  ResultsStore store(base, false, {{"mode", "run"}});
  store.set_metadata({{"name", "grid"}, {"cases", 24}});
  run_sweep(cases, fake_run, store, nullptr);
  store.mark_complete();
  store.write_exports();
}

TEST(Shard, EveryCaseFallsInExactlyOneShardRoundRobin) {
  const auto cases = matrix_cases();
  std::vector<int> seen(cases.size(), 0);
  for (std::size_t k = 1; k <= 5; ++k) {
    const auto mine = shard_cases(cases, {k, 5});
    for (const CaseSpec& c : mine) {
      ++seen[c.index];
      EXPECT_EQ(c.index % 5, k - 1);
    }
    EXPECT_GE(mine.size(), 4u);  // 24 over 5: four or five each
    EXPECT_LE(mine.size(), 5u);
  }
  EXPECT_EQ(seen, std::vector<int>(cases.size(), 1));
  EXPECT_EQ(shard_base("out/grid", {2, 5}), "out/grid.shard-2-of-5");
}

TEST(Shard, ParseAcceptsKOfNAndRejectsTheRestNamingTheFlag) {
  EXPECT_EQ(parse_shard("3/8", "--shard").index, 3u);
  EXPECT_EQ(parse_shard("3/8", "--shard").count, 8u);
  for (const char* bad : {"0/4", "5/4", "4", "a/b", "1/0", "-1/4", "1/4/2"}) {
    try {
      parse_shard(bad, "--shard");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const SweepError& error) {
      EXPECT_EQ(std::string(error.what()).rfind(std::string("--shard ") + bad + ": allowed", 0), 0u)
          << error.what();
    }
  }
}

TEST(Shard, MergedShardsExportTheSameCsvAndJsonAsAnUnshardedRun) {
  ScratchFolder scratch;
  const auto cases = matrix_cases();
  run_into(scratch.path() / "whole" / "grid", cases);
  const auto base = scratch.path() / "sharded" / "grid";
  // Shards in reverse order: the merge orders by case, not by when shards finished.
  for (std::size_t k = 3; k >= 1; --k)
    run_into(shard_base(base, {k, 3}), shard_cases(cases, {k, 3}));
  const MergeSummary summary = merge_shards(base);
  EXPECT_EQ(summary.shards, 3u);
  EXPECT_EQ(summary.rows, 24u);
  const std::string whole_csv = read_text(scratch.path() / "whole" / "grid.csv");
  EXPECT_EQ(std::count(whole_csv.begin(), whole_csv.end(), '\n'), 25);
  EXPECT_EQ(read_text(base.string() + ".csv"), whole_csv);
  EXPECT_EQ(read_text(base.string() + ".json"), read_text(scratch.path() / "whole" / "grid.json"));
  // The merged store is a whole result set: it resumes with nothing left to run.
  ResultsStore resumed(base, true, {{"mode", "run"}});
  EXPECT_EQ(resumed.resumed_rows(), 24u);
}

TEST(Shard, MergeRefusesAMissingOrIncompleteShard) {
  ScratchFolder scratch;
  const auto cases = matrix_cases();
  const auto base = scratch.path() / "grid";
  EXPECT_THROW(merge_shards(base), SweepError);  // nothing to merge
  run_into(shard_base(base, {1, 2}), shard_cases(cases, {1, 2}));
  try {
    merge_shards(base);
    ADD_FAILURE() << "merged without shard 2";
  } catch (const SweepError& error) {
    EXPECT_NE(std::string(error.what()).find("grid.shard-2-of-2.sqlite: missing"),
              std::string::npos)
        << error.what();
  }
  {  // shard 2 interrupted: some rows, never marked complete
    ResultsStore partial(shard_base(base, {2, 2}), false, {{"mode", "run"}});
    run_sweep({shard_cases(cases, {2, 2}).front()}, fake_run, partial, nullptr);
  }
  try {
    merge_shards(base);
    ADD_FAILURE() << "merged an incomplete shard";
  } catch (const SweepError& error) {
    EXPECT_NE(std::string(error.what()).find("shard 2/2 is incomplete"), std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(std::filesystem::exists(base.string() + ".csv"));
}

TEST(Shard, MergeRefusesShardsOfDifferentSweepsNamingTheDifference) {
  ScratchFolder scratch;
  const auto cases = matrix_cases();
  const auto base = scratch.path() / "grid";
  run_into(shard_base(base, {1, 2}), shard_cases(cases, {1, 2}));
  {
    ResultsStore other(shard_base(base, {2, 2}), false, {{"mode", "stability"}});
    other.mark_complete();
  }
  try {
    merge_shards(base);
    ADD_FAILURE() << "merged two different sweeps";
  } catch (const SweepError& error) {
    EXPECT_NE(std::string(error.what()).find("mode 'run' -> 'stability'"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace clothlab::sweep
