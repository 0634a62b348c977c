// The clothlab program's stability verdict, sweeps and dt search end to end, on tiny grids.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <string_view>

#include "../support/read_text.hpp"
#include "../support/sanitizer.hpp"

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string out, err;
};

using clothlab::testing::read_text;

nlohmann::json read_json(const fs::path& path) { return nlohmann::json::parse(read_text(path)); }

class ClothlabStability : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() /
              ("clothlab_stability_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path file(const std::string& name) const { return folder_ / name; }

  Outcome run(const std::string& arguments) const {
    return run_without_builtin_path("--plugin-path '" CLOTHLAB_BUILTIN_PLUGIN_DIR "' " + arguments);
  }

  Outcome run_without_builtin_path(const std::string& arguments) const {
    const std::string command = "cd '" + folder_.string() +
                                "' && env -u CLOTHLAB_PLUGIN_PATH '" CLOTHLAB_EXECUTABLE "' " +
                                arguments + " > stdout.txt 2> stderr.txt";
    const int status = std::system(command.c_str());
    Outcome outcome;
    outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    outcome.out = read_text(file("stdout.txt"));
    outcome.err = read_text(file("stderr.txt"));
    return outcome;
  }

  void write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name)) << text;
  }

  fs::path folder_;
};

// A 6x6 sheet of 0.3 kg: 8.3 g per particle. With ks = 1e4 N/m a particle's stiffest mode has
// w ~ sqrt(4 ks / m) ~ 2.2e3 rad/s, so w dt ~ 44 at dt = 20 ms: far outside RK4's stability
// interval (2.8) and the state must blow up within a few steps.
const std::string tiny_sheet = "--scenario sheet --set scenario.rows=6 --set scenario.cols=6 ";

TEST_F(ClothlabStability, CalmRunIsJudgedStable) {
  const Outcome outcome =
      run(tiny_sheet + "--integrator rk4 --dt 0.001 --duration 0.2 --json run.json --quiet");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto json = read_json(file("run.json"));
  EXPECT_TRUE(json["stable"].get<bool>());
  EXPECT_TRUE(json["failed_check"].is_null());
  EXPECT_TRUE(json["failed_step"].is_null());
  // 200 steps checked every 10: 20 checks.
  EXPECT_EQ(json["stability_checks"].get<int>(), 20);
}

TEST_F(ClothlabStability, DivergentRunIsFlaggedAndStops) {
  const Outcome outcome = run(tiny_sheet +
                              "--set scenario.structural.ks=1e4 --set scenario.shear.ks=1e4 "
                              "--integrator rk4 --dt 0.02 --duration 2 --set stability.interval=1 "
                              "--json run.json --quiet");
  ASSERT_EQ(outcome.exit_code, 3) << outcome.err;
  const auto json = read_json(file("run.json"));
  EXPECT_FALSE(json["stable"].get<bool>());
  ASSERT_TRUE(json["failed_check"].is_string());
  EXPECT_NE(json["failed_check"].get<std::string>(), "");
  const int failed_step = json["failed_step"].get<int>();
  EXPECT_GE(failed_step, 1);
  EXPECT_LT(failed_step, 100);  // of the 100 requested: the run stopped at the verdict
  EXPECT_EQ(json["steps"].get<int>(), failed_step);
  EXPECT_NE(outcome.err.find("run diverged"), std::string::npos);
}

TEST_F(ClothlabStability, BadMonitorSettingIsRejected) {
  const Outcome outcome = run(tiny_sheet + "--set stability.max_stretch=0.5");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_NE(outcome.err.find("stability.max_stretch = 0.5"), std::string::npos) << outcome.err;
}

// stability.stretch_stop ends a run (exit 0, not a failure) at the first check past it; the
// default soft sheet hanging from two corners soon stretches past 5 %.
TEST_F(ClothlabStability, StretchStopEndsTheRunAtTheFirstCheckPastIt) {
  const Outcome outcome = run(tiny_sheet +
                              "--integrator rk4 --dt 0.001 --duration 1 --set "
                              "stability.stretch_stop=1.05 --json run.json --quiet");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto json = read_json(file("run.json"));
  EXPECT_TRUE(json["stable"].get<bool>());
  EXPECT_TRUE(json["stretch_stopped"].get<bool>());
  const int steps = json["steps"].get<int>();
  EXPECT_LT(steps, 1000);
  EXPECT_EQ(steps % 10, 0);  // at a check
  EXPECT_GT(json["max_stretch"]["over_run"].get<double>(), 1.05);
  // The stop judges the robust figure, the springs at the pins left out.
  EXPECT_GT(json["max_stretch_away_from_pins"]["over_run"].get<double>(), 1.05);
  EXPECT_NE(json["verdict"].get<std::string>().find("stopped at step " + std::to_string(steps)),
            std::string::npos);
  EXPECT_NE(json["verdict"].get<std::string>().find("away from the pins"), std::string::npos);
  // Without it the same run goes to the end.
  ASSERT_EQ(run(tiny_sheet + "--integrator rk4 --dt 0.001 --duration 1 --json full.json --quiet")
                .exit_code,
            0);
  EXPECT_FALSE(read_json(file("full.json"))["stretch_stopped"].get<bool>());
  EXPECT_EQ(read_json(file("full.json"))["steps"].get<int>(), 1000);
  // A run the monitor fails at the same check keeps the monitor's verdict.
  const Outcome diverged = run(tiny_sheet +
                               "--set scenario.structural.ks=1e4 --set scenario.shear.ks=1e4 "
                               "--integrator rk4 --dt 0.02 --duration 2 --set stability.interval=1 "
                               "--set stability.stretch_stop=1.05 --json diverged.json --quiet");
  EXPECT_EQ(diverged.exit_code, 3) << diverged.err;
  EXPECT_FALSE(read_json(file("diverged.json"))["stretch_stopped"].get<bool>());
  EXPECT_FALSE(read_json(file("diverged.json"))["stable"].get<bool>());
  const Outcome bad = run(tiny_sheet + "--set stability.stretch_stop=0.5");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("stability.stretch_stop = 0.5: out of range; allowed: 0 (run to the "
                         "end) or a real in [1, 1e6]"),
            std::string::npos)
      << bad.err;
}

// The key table's range is the one the search accepts: a width it would refuse is caught as
// bad input with the allowed range, before any probe runs.
TEST_F(ClothlabStability, SearchToleranceOutsideTheSearchsRangeIsBadInput) {
  const Outcome outcome = run(tiny_sheet + "--find-max-dt --set find_max_dt.tolerance=1");
  EXPECT_EQ(outcome.exit_code, 1) << outcome.err;
  EXPECT_NE(outcome.err.find("--set: find_max_dt.tolerance = 1: out of range"), std::string::npos)
      << outcome.err;
  EXPECT_NE(outcome.err.find("allowed: real in [1e-06, 0.5]"), std::string::npos) << outcome.err;
}

const std::string four_case_sweep = R"(scenario: {rows: 5, cols: 5}
duration: 0.05
sweep:
  name: four
  mode: run
  output: ignored/four
  matrix:
    integrator: [euler, rk4]
    scenario: [sheet]
    dt: [0.001, 0.002]
)";

// One key table validates sweeps and single runs: the same bad value gets the same message
// (after the source), before any case runs.
TEST_F(ClothlabStability, ASweepsBadValueGetsTheSingleRunsMessage) {
  const auto message_after_source = [](const std::string& err) {
    const std::size_t key = err.find("dt = ");
    return key == std::string::npos ? err : err.substr(key);
  };
  const Outcome single = run(tiny_sheet + "--dt -1 --duration 0.05");
  write("bad-dt.yaml",
        "duration: 0.05\nsweep:\n  name: bad\n  output: bad\n  matrix:\n"
        "    integrator: [euler]\n    dt: [0.001, -1]\n");
  const Outcome swept = run("--config bad-dt.yaml --out results");
  EXPECT_EQ(single.exit_code, 1);
  EXPECT_EQ(swept.exit_code, 1);
  EXPECT_NE(swept.err.find("bad-dt.yaml:7:"), std::string::npos) << swept.err;
  EXPECT_EQ(message_after_source(swept.err), message_after_source(single.err)) << swept.err;
  EXPECT_FALSE(fs::exists(file("results") / "bad.csv"));
}

TEST_F(ClothlabStability, SweepResumeRunsOnlyMissingCases) {
  write("four.yaml", four_case_sweep);
  const Outcome first = run("--config four.yaml --out results");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto rows = read_json(file("results/four.json"))["rows"];
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) EXPECT_EQ(row["status"], "stable") << row.dump();

  const Outcome again = run("--config four.yaml --out results --resume");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("0 stable, 0 unstable, 0 failed, 4 already done"), std::string::npos)
      << again.out;
  // Same rows, same measurements: nothing was re-run.
  EXPECT_EQ(read_json(file("results/four.json"))["rows"], rows);

  // An interrupted sweep: the store lacks its last row. Resuming runs that case alone.
  sqlite3* store = nullptr;
  ASSERT_EQ(sqlite3_open(file("results/four.sqlite").c_str(), &store), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(store, "DELETE FROM rows WHERE seq = (SELECT max(seq) FROM rows)", nullptr,
                         nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(store);
  const Outcome partial = run("--config four.yaml --out results --resume");
  ASSERT_EQ(partial.exit_code, 0) << partial.err;
  EXPECT_NE(partial.out.find("1 stable, 0 unstable, 0 failed, 3 already done"), std::string::npos)
      << partial.out;
  EXPECT_EQ(read_json(file("results/four.json"))["rows"].size(), 4u);

  // Atomic writes: the store, its lock and the two exports, no temporaries; the CSV has 4 rows.
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(file("results")))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"four.csv", "four.json", "four.lock", "four.sqlite"}));
  std::ifstream csv(file("results/four.csv"));
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 5);
}

// The rows without the columns that measure time (they differ from run to run).
nlohmann::json without_timings(nlohmann::json document) {
  for (auto& row : document["rows"])
    for (const char* timing : {"wall_time_s", "ms_per_step", "ms_per_step_p90",
                               "springs_per_second", "real_time_factor"})
      row.erase(timing);
  return document;
}

TEST_F(ClothlabStability, ShardsMergedByClothlabMergeEqualAnUnshardedRun) {
  write("four.yaml", four_case_sweep);
  ASSERT_EQ(run("--config four.yaml --out whole").exit_code, 0);
  for (const char* shard : {"2/3", "1/3", "3/3"}) {
    const Outcome part = run(std::string("--config four.yaml --out parts --shard ") + shard);
    ASSERT_EQ(part.exit_code, 0) << part.err;
    EXPECT_NE(part.out.find("clothlab merge parts/four"), std::string::npos) << part.out;
  }
  EXPECT_FALSE(fs::exists(file("parts/four.csv")));  // shards write only their stores
  const Outcome merged = run_without_builtin_path("merge parts/four");
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_EQ(merged.out,
            "merged 3 shards of parts/four: 4 rows\n  results: parts/four.csv, "
            "parts/four.json\n");
  const auto whole = read_json(file("whole/four.json")), parts = read_json(file("parts/four.json"));
  ASSERT_EQ(parts["rows"].size(), 4u);
  EXPECT_EQ(without_timings(parts), without_timings(whole));
  // A shard missing: merge says which, in one line, exit 1.
  fs::remove(file("parts/four.shard-2-of-3.sqlite"));
  const Outcome incomplete = run_without_builtin_path("merge parts/four");
  EXPECT_EQ(incomplete.exit_code, 1);
  EXPECT_EQ(incomplete.err,
            "clothlab: error: parts/four.shard-2-of-3.sqlite: missing; run shard "
            "2/3\n");
}

TEST_F(ClothlabStability, SweepResumeAfterAConfigEditIsRefusedNamingWhatChanged) {
  write("four.yaml", four_case_sweep);
  ASSERT_EQ(run("--config four.yaml --out results").exit_code, 0);
  const std::string rows_before = read_text(file("results/four.json"));
  std::string edited = four_case_sweep;
  edited.replace(edited.find("duration: 0.05"), 14, "duration: 0.005");
  write("four.yaml", edited);
  const Outcome resumed = run("--config four.yaml --out results --resume");
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_EQ(resumed.err,
            "clothlab: error: results/four.sqlite: cannot resume: the sweep changed since these "
            "results were written: setting.duration '0.05' -> '0.005'; run without --resume to "
            "replace them, or use another --out\n");
  EXPECT_EQ(read_text(file("results/four.json")), rows_before);  // nothing mixed in
  // Without --resume the edited sweep starts a new result set.
  const Outcome fresh = run("--config four.yaml --out results");
  ASSERT_EQ(fresh.exit_code, 0) << fresh.err;
  const auto fresh_rows = read_json(file("results/four.json"));  // the loop must not outlive it
  ASSERT_EQ(fresh_rows["rows"].size(), 4u);
  for (const auto& row : fresh_rows["rows"]) {
    // duration 0.005 s in whole steps of dt: [0.005, 0.005 + dt), far from the old 0.05 s.
    const double dt = std::stod(row["dt"].get<std::string>());
    EXPECT_GE(row["sim_time_s"].get<double>(), 0.005 - 1e-12) << row.dump();
    EXPECT_LT(row["sim_time_s"].get<double>(), 0.005 + dt) << row.dump();
  }
}

TEST_F(ClothlabStability, SweepResumeWithARebuiltPluginIsRefusedNamingThePlugin) {
  write("four.yaml", four_case_sweep);
  fs::create_directories(file("plugins"));
  for (const char* plugin : {"euler.so", "rk4.so", "sheet.so"})
    fs::copy_file(fs::path(CLOTHLAB_BUILTIN_PLUGIN_DIR) / plugin, file("plugins") / plugin);
  const std::string sweep = "--config four.yaml --out results --plugin-path plugins";
  ASSERT_EQ(run_without_builtin_path(sweep).exit_code, 0);
  std::ofstream(file("plugins/rk4.so"), std::ios::app | std::ios::binary) << '\0';
  const Outcome resumed = run_without_builtin_path(sweep + " --resume");
  EXPECT_EQ(resumed.exit_code, 1);
  const std::string change =
      "cannot resume: the sweep changed since these results were "
      "written: plugin.rk4 '" +
      fs::absolute(file("plugins/rk4.so")).string() + " size ";
  EXPECT_NE(resumed.err.find(change), std::string::npos) << resumed.err;
  EXPECT_EQ(resumed.err.find("plugin.euler"), std::string::npos) << resumed.err;
}

// The same 36 cases twice (different dt), both writing results/same.*, started together: one
// sweep gets the results, the other is refused in one line; no row is lost or mixed in.
TEST_F(ClothlabStability, TwoSweepsWritingTheSameOutputAtOnceLoseNoRows) {
  const std::string sweep = R"(scenario: {rows: 6, cols: 6}
steps: 4000
threads: 1
sweep:
  name: same
  mode: run
  matrix:
    integrator: [euler, midpoint, rk4]
    scenario: [sheet]
    scenario.structural.ks: [10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000, 50000]
    dt: [DT]
)";
  for (const char* dt : {"0.001", "0.002"}) {
    std::string text = sweep;
    text.replace(text.find("DT"), 2, dt);
    write(std::string("dt-") + dt + ".yaml", text);
  }
  const std::string clothlab = "env -u CLOTHLAB_PLUGIN_PATH '" CLOTHLAB_EXECUTABLE
                               "' --plugin-path '" CLOTHLAB_BUILTIN_PLUGIN_DIR "' --out results";
  const std::string both =
      "cd '" + folder_.string() + "' && { (" + clothlab +
      " --config dt-0.001.yaml > a.out 2> a.err; echo $? > a.status) & (" + clothlab +
      " --config dt-0.002.yaml > b.out 2> b.err; echo $? > b.status) & wait; }";
  ASSERT_EQ(std::system(both.c_str()), 0);
  const std::string a_status = read_text(file("a.status")), b_status = read_text(file("b.status"));
  ASSERT_TRUE((a_status == "0\n") != (b_status == "0\n"))
      << "a: " << a_status << read_text(file("a.err")) << "b: " << b_status
      << read_text(file("b.err"));
  const std::string loser = a_status == "0\n" ? "b" : "a";
  const std::string winner_dt = a_status == "0\n" ? "0.001" : "0.002";
  EXPECT_EQ(read_text(file(loser + ".status")), "1\n");
  const std::string refusal = read_text(file(loser + ".err"));
  EXPECT_NE(refusal.find("clothlab: error: results/same.sqlite: another clothlab process (pid "),
            std::string::npos)
      << refusal;
  EXPECT_EQ(std::count(refusal.begin(), refusal.end(), '\n'), 1) << refusal;
  const auto rows = read_json(file("results/same.json"))["rows"];
  ASSERT_EQ(rows.size(), 36u);
  for (const auto& row : rows) EXPECT_EQ(row["dt"], winner_dt) << row.dump();
}

using clothlab::testing::address_sanitizer;

// "crashed: exited with status N before reporting", N > 0: the reason the sweep records for a
// child that ended without answering (host/process), followed by the plugin call it was in
// (" in test-crash.step (...) at step 1") when it was in one.
bool is_failed_exit(std::string_view reason) {
  constexpr std::string_view prefix = "crashed: exited with status ", suffix = " before reporting";
  const size_t suffix_at = reason.find(suffix);
  if (!reason.starts_with(prefix) || suffix_at == std::string_view::npos ||
      suffix_at <= prefix.size())
    return false;
  const std::string_view rest = reason.substr(suffix_at + suffix.size());
  if (!rest.empty() && !rest.starts_with(" in ")) return false;
  const std::string_view number = reason.substr(prefix.size(), suffix_at - prefix.size());
  int status = 0;
  const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), status);
  return error == std::errc() && end == number.data() + number.size() && status > 0;
}

// The failed row's reason for a child killed by SIGSEGV. In a sanitizer build (CLOTHLAB_SANITIZE:
// ASan with UBSan) the child reports the null store on stderr and exits with a non-zero status
// instead: ASan's SEGV handler, or UBSan first when it halts on errors.
bool is_segfault_record(const std::string& reason, const std::string& err) {
  if (reason.starts_with("crashed: signal 11 ")) return true;
  const bool reported = err.find("AddressSanitizer: SEGV") != std::string::npos ||
                        err.find("runtime error: store to null pointer") != std::string::npos;
  return address_sanitizer && is_failed_exit(reason) && reported;
}

// Items 1 and 6 of issue 12: a bad value in a sweep (here a byte that is not UTF-8) was found
// per case, after others ran; its error text made the forked child escape and fork again
// (12 cases -> 4096 processes, exit 0). Now every case is checked before the first one runs.
TEST_F(ClothlabStability, ASweepWithBadInputIsRefusedBeforeAnyCaseRuns) {
  const std::string matrix = R"(duration: 0.01
sweep:
  name: bad
  mode: run
  matrix:
    integrator: [euler, rk4, midpoint]
    scenario: [sheet]
    mesh: [3, 4]
    dt: [0.001, 0.002]
)";
  write("bad.yaml", "scenario: {mass: \"\xff\"}\n" + matrix);
  const Outcome bad_byte = run("--config bad.yaml --out results");
  EXPECT_EQ(bad_byte.exit_code, 1) << bad_byte.err;
  EXPECT_EQ(std::count(bad_byte.err.begin(), bad_byte.err.end(), '\n'), 1) << bad_byte.err;
  EXPECT_NE(bad_byte.err.find("bad.yaml:1:18: scenario.mass = "), std::string::npos)
      << bad_byte.err;
  EXPECT_EQ(bad_byte.out, "");
  EXPECT_FALSE(fs::exists(file("results/bad.json")));

  write("typo.yaml",
        "plugin_params: {verlett: {damping: 0.5}}\nscenario: {rows: 3, cols: 3}\n" + matrix);
  const Outcome typo = run("--config typo.yaml --out results");
  EXPECT_EQ(typo.exit_code, 1) << typo.err;
  EXPECT_NE(typo.err.find("typo.yaml:1:36: plugin_params.verlett.damping: no plugin has the id "
                          "verlett; allowed ids: "),
            std::string::npos)
      << typo.err;

  write("range.yaml", "scenario: {structural: {ks: -1}}\n" + matrix);
  const Outcome range = run("--config range.yaml --out results");
  EXPECT_EQ(range.exit_code, 1) << range.err;
  EXPECT_NE(range.err.find("range.yaml:1:29: "), std::string::npos) << range.err;
  EXPECT_FALSE(fs::exists(file("results")));
}

// Item 4: 64 two-valued axes wrapped the case count to 0 (exit 0, nothing checked), 20 took
// 3.9 GB. The count is bounded while it is computed.
TEST_F(ClothlabStability, AMatrixBeyondTheCaseLimitIsRefused) {
  for (const int axes : {20, 64}) {
    std::string yaml =
        "duration: 0.01\nsweep:\n  name: big\n  matrix:\n    integrator: [rk4]\n"
        "    dt: [0.001]\n";
    for (int k = 0; k < axes; ++k) yaml += "    scenario.k" + std::to_string(k) + ": [1, 2]\n";
    write("big.yaml", yaml);
    const Outcome outcome = run("--config big.yaml --out results");
    EXPECT_EQ(outcome.exit_code, 1) << outcome.err;
    EXPECT_NE(outcome.err.find("big.yaml: sweep.matrix has more than 100000 cases (at axis "
                               "scenario.k16); allowed: at most 100000"),
              std::string::npos)
        << outcome.err;
  }
}

// Items 6 and 7: --set dt=0.002 --dt 0.001 took 0.002 silently; a value with a line break made
// a two-line error; an unknown plugin in a config named no position.
TEST_F(ClothlabStability, CommandLineAndConfigErrorsAreOneLineWithTheirSource) {
  const Outcome conflict = run("--set dt=0.002 --dt 0.001 --steps 1");
  EXPECT_EQ(conflict.exit_code, 1);
  EXPECT_EQ(conflict.err,
            "clothlab: error: --dt 0.001 conflicts with --set dt=0.002; allowed: one of them\n");
  write("threads.yaml", "threads: \"a\\nb\"\nsteps: 1\n");
  const Outcome threads = run("--config threads.yaml");
  EXPECT_EQ(threads.exit_code, 1);
  EXPECT_EQ(std::count(threads.err.begin(), threads.err.end(), '\n'), 1) << threads.err;
  EXPECT_NE(threads.err.find("threads = a\\nb"), std::string::npos) << threads.err;
  write("unknown.yaml", "integrator: nosuch\nsteps: 1\n");
  const Outcome unknown = run("--config unknown.yaml");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(unknown.err.rfind("clothlab: error: unknown.yaml:1:13: integrator = nosuch: ", 0), 0u)
      << unknown.err;
  const Outcome empty_path = run("--config '' --steps 1");
  EXPECT_EQ(empty_path.exit_code, 1);
  EXPECT_EQ(empty_path.err, "clothlab: error: --config = '': an empty path; allowed: a path\n");
  const Outcome many_threads = run("--threads 4096 --steps 1");
  EXPECT_EQ(many_threads.exit_code, 1);
  EXPECT_NE(
      many_threads.err.find("--threads: threads = 4096: out of range; allowed: int in [0, 256]"),
      std::string::npos)
      << many_threads.err;
}

// Item 5 of issue 12: an output path naming a FIFO or device was replaced by a regular file,
// and a bad output was found only after the work. Now it is refused before anything runs.
TEST_F(ClothlabStability, AnOutputThatIsNotARegularFileIsRefusedBeforeTheRun) {
  write("fifo.yaml", R"(scenario: {rows: 4, cols: 4}
duration: 0.01
sweep:
  name: fifo
  mode: run
  matrix:
    integrator: [rk4]
    dt: [0.001]
)");
  fs::create_directories(file("results"));
  ASSERT_EQ(::mkfifo(file("results/fifo.json").c_str(), 0600), 0);
  const Outcome sweep = run("--config fifo.yaml --out results");
  EXPECT_EQ(sweep.exit_code, 1);
  EXPECT_NE(sweep.err.find("results/fifo.json: it is a FIFO"), std::string::npos) << sweep.err;
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(file("results/fifo.json"))));
  EXPECT_FALSE(fs::exists(file("results/fifo.csv")));

  // A private null device (never /dev/null: a broken build run as root would replace it).
  if (::mknod(file("null-device").c_str(), S_IFCHR | 0666, ::makedev(1, 3)) != 0)
    GTEST_SKIP() << "mknod needs root; the FIFO case above ran";
  const Outcome single =
      run("--steps 2 --set scenario.rows=4 --set scenario.cols=4 --json null-device");
  EXPECT_EQ(single.exit_code, 1);
  EXPECT_EQ(single.err,
            "clothlab: error: cannot write null-device: it is a device; allowed: a regular file or "
            "a new name\n");
  EXPECT_EQ(single.out, "");
  EXPECT_TRUE(fs::is_character_file(file("null-device")));
}

// Item 2 of issue 12: a hanging case hung the sweep forever. Now the `timeout` key bounds
// every case's child; the case is a failed row and the sweep goes on.
TEST_F(ClothlabStability, HangingCaseTimesOutAndTheSweepGoesOn) {
  write("hang.yaml", R"(scenario: {rows: 4, cols: 4}
duration: 0.01
timeout: 0.5
sweep:
  name: hang
  mode: run
  matrix:
    integrator: [clothlab_test_hang, rk4]
    scenario: [sheet]
    dt: [0.001]
)");
  const Outcome outcome =
      run("--config hang.yaml --out results --plugin-path '" CLOTHLAB_HANG_PLUGIN_DIR "'");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto rows = read_json(file("results/hang.json"))["rows"];
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["status"], "failed");
  // The call it hung in follows: " in hangs-in-step.step (.../clothlab_test_hang.so) at step 1".
  EXPECT_EQ(rows[0]["reason"].get<std::string>().rfind(
                "timed out after 0.5 s in hangs-in-step.step (", 0),
            0u)
      << rows[0].dump();
  EXPECT_EQ(rows[1]["status"], "stable");
}

// A single run whose plugin crashes exits 2 (a plugin error) with a one-line reason, not 139,
// that names the plugin's id, the phase, the library and the step.
TEST_F(ClothlabStability, CrashingSingleRunExitsTwoWithTheReason) {
  const Outcome outcome = run(
      "--integrator clothlab_test_crash --scenario sheet --steps 3 "
      "--set scenario.rows=4 --set scenario.cols=4 --plugin-path '" CLOTHLAB_CRASH_PLUGIN_DIR "'");
  EXPECT_EQ(outcome.exit_code, 2) << outcome.err;
  EXPECT_NE(outcome.err.find("clothlab: error: crashed: "), std::string::npos) << outcome.err;
  const std::string library =
      (fs::path(CLOTHLAB_CRASH_PLUGIN_DIR) / "clothlab_test_crash.so").string();
  EXPECT_NE(outcome.err.find(" in test-crash.step (" + library + ") at step 1"), std::string::npos)
      << outcome.err;
  // A sanitizer build's child reports the null store on stderr too.
  if (!address_sanitizer) {
    EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1) << outcome.err;
  }
}

TEST_F(ClothlabStability, CrashingCaseIsAFailedRowAndTheSweepGoesOn) {
  write("crash.yaml", R"(scenario: {rows: 4, cols: 4}
duration: 0.01
sweep:
  name: crash
  mode: run
  matrix:
    integrator: [clothlab_test_crash, rk4]
    scenario: [sheet]
    dt: [0.001]
)");
  const Outcome outcome =
      run("--config crash.yaml --out results --plugin-path '" CLOTHLAB_CRASH_PLUGIN_DIR "'");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto rows = read_json(file("results/crash.json"))["rows"];
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["status"], "failed");
  EXPECT_TRUE(is_segfault_record(rows[0]["reason"].get<std::string>(), outcome.err))
      << rows[0].dump() << "\n"
      << outcome.err;
  EXPECT_EQ(rows[1]["status"], "stable");
}

// Issue 23: the cases of a sweep share one worker child, replaced after a crash or a timeout.
// The cases after a crashing and a hanging one give the same rows as in a sweep without them,
// timings aside: nothing of the killed workers reaches the next case.
TEST_F(ClothlabStability, RowsAfterACrashAndAHangEqualThoseOfASweepWithoutThem) {
  const auto sweep = [](const std::string& name, const std::string& integrators) {
    return "scenario: {rows: 4, cols: 4}\nduration: 0.01\ntimeout: 1\nsweep:\n  name: " + name +
           "\n  mode: run\n  matrix:\n    dt: [0.001, 0.002]\n    integrator: [" + integrators +
           "]\n";
  };
  write("faulty.yaml",
        sweep("faulty", "rk4, clothlab_test_crash, euler, clothlab_test_hang, midpoint"));
  write("sound.yaml", sweep("sound", "rk4, euler, midpoint"));
  const std::string faulty_plugins =
      " --plugin-path '" CLOTHLAB_CRASH_PLUGIN_DIR "' --plugin-path '" CLOTHLAB_HANG_PLUGIN_DIR "'";
  const Outcome faulty = run("--config faulty.yaml --out results" + faulty_plugins);
  ASSERT_EQ(faulty.exit_code, 0) << faulty.err;
  const Outcome sound = run("--config sound.yaml --out results");
  ASSERT_EQ(sound.exit_code, 0) << sound.err;

  const auto without_timings = [](nlohmann::json row) {
    for (const char* timing : {"wall_time_s", "ms_per_step", "ms_per_step_p90",
                               "springs_per_second", "real_time_factor"})
      row.erase(timing);
    return row;
  };
  std::map<std::string, nlohmann::json> sound_rows;
  const auto sound_json = read_json(file("results/sound.json"));
  for (const auto& row : sound_json["rows"]) sound_rows[row["key"]] = without_timings(row);
  ASSERT_EQ(sound_rows.size(), 6u);
  const auto faulty_rows = read_json(file("results/faulty.json"))["rows"];
  ASSERT_EQ(faulty_rows.size(), 10u);
  std::size_t compared = 0;
  for (const auto& row : faulty_rows) {
    const std::string integrator = row["integrator"];
    if (integrator == "clothlab_test_crash" || integrator == "clothlab_test_hang") {
      EXPECT_EQ(row["status"], "failed") << row.dump();
      if (integrator == "clothlab_test_hang") {
        EXPECT_TRUE(row["reason"].get<std::string>().starts_with("timed out after 1 s in "))
            << row.dump();
      }
      continue;
    }
    ASSERT_EQ(sound_rows.count(row["key"]), 1u) << row.dump();
    EXPECT_EQ(without_timings(row), sound_rows[row["key"]]);
    EXPECT_EQ(row["status"], "stable") << row.dump();
    ++compared;
  }
  EXPECT_EQ(compared, 6u);
}

// A case whose solver missed its tolerance is not a passing case: the sweep records it as
// unstable by the check "unconverged" at its first missed step; the same case with enough
// iterations passes.
TEST_F(ClothlabStability, ASweepCaseWhoseSolverMissedItsToleranceDoesNotPass) {
  write("solver.yaml", R"(scenario: {plugin: sheet, rows: 4, cols: 5}
integrator: {tolerance: 1.0e-14}
dt: 0.01
steps: 10
sweep:
  name: solver
  mode: run
  matrix:
    integrator: [implicit_euler]
    integrator.max_iterations: [1, 1000]
)");
  const Outcome outcome = run("--config solver.yaml --out results");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto rows = read_json(file("results/solver.json"))["rows"];
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["status"], "unstable") << rows[0].dump();
  EXPECT_EQ(rows[0]["check"], "unconverged");
  EXPECT_EQ(rows[0]["fail_step"], 1);
  EXPECT_EQ(
      rows[0]["reason"].get<std::string>().rfind(
          "unconverged: the solver missed its tolerance in 10 of 10 steps (first at step 1)", 0),
      0u)
      << rows[0].dump();
  EXPECT_EQ(rows[1]["status"], "stable") << rows[1].dump();
}

// On a terminal --find-max-dt shows each probe on the sweeps' progress line (stderr); through a
// pipe it writes none of it. script(1) gives the program a terminal and records what it wrote.
TEST_F(ClothlabStability, FindMaxDtShowsItsProbesOnATerminalOnly) {
  const std::string search = tiny_sheet +
                             "--integrator midpoint --duration 0.05 --find-max-dt "
                             "--set find_max_dt.tolerance=0.5 --set find_max_dt.max_evaluations=9";
  const Outcome piped = run(search);
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.err, "");
  const std::string on_terminal =
      "cd '" + folder_.string() +
      "' && env -u CLOTHLAB_PLUGIN_PATH script -qec \"'" CLOTHLAB_EXECUTABLE
      "' --plugin-path '" CLOTHLAB_BUILTIN_PLUGIN_DIR "' " +
      search + "\" terminal.txt > /dev/null";
  ASSERT_EQ(std::system(on_terminal.c_str()), 0);
  const std::string terminal = read_text(file("terminal.txt"));
  EXPECT_NE(terminal.find("\r[1/9]"), std::string::npos) << terminal;
  EXPECT_NE(terminal.find("s: stable"), std::string::npos) << terminal;
  EXPECT_NE(terminal.find("s: unstable ("), std::string::npos) << terminal;
  EXPECT_NE(terminal.find("measured  dt_max"), std::string::npos) << terminal;
}

TEST_F(ClothlabStability, FoundMaxDtIsStableAndTwentyPercentMoreIsNot) {
  const std::string scene = tiny_sheet + "--integrator midpoint --duration 0.5 ";
  const Outcome search = run(scene +
                             "--find-max-dt --set find_max_dt.tolerance=0.02 "
                             "--json search.json");
  ASSERT_EQ(search.exit_code, 0) << search.err;
  const auto json = read_json(file("search.json"));
  ASSERT_EQ(json["outcome"], "bracketed") << json.dump();
  const double dt_max = json["dt_max"].get<double>();
  EXPECT_LE(json["dt_unstable"].get<double>(), dt_max * 1.021);
  EXPECT_NE(search.out.find("predicted dt_max"), std::string::npos);
  // Predicted from midpoint's declared table (clothlab.explicit-scheme/1), not from its id.
  EXPECT_TRUE(json["predicted_dt_max"].is_number()) << json.dump();
  EXPECT_FALSE(json.contains("prediction_error")) << json.dump();

  char dt_text[64];
  std::snprintf(dt_text, sizeof dt_text, "%.17g", dt_max);
  EXPECT_EQ(run(scene + "--quiet --dt " + dt_text).exit_code, 0);
  std::snprintf(dt_text, sizeof dt_text, "%.17g", 1.2 * dt_max);
  EXPECT_EQ(run(scene + "--quiet --dt " + dt_text).exit_code, 3);
}

}  // namespace
