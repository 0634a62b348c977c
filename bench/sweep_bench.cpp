// Per-case overhead of the sweep machinery, without physics:
//   BM_StoreAppend/N      one row appended to a results store that already holds N rows
//                         (the store's cost per case; O(1) means flat in N);
//   BM_SweepPerCase/N     a whole sweep of N trivial cases: each case sent to the sweep's
//                         worker child (process::Worker), its answer parsed and its row
//                         stored; the ms_per_case counter is the sweep's own overhead per case.
// Run: build/bin/clothlab_sweep_bench (figures in lab/sweeps.md).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <clothlab/process/isolation.hpp>
#include <clothlab/sweep/results_store.hpp>
#include <clothlab/sweep/sweep_runner.hpp>
#include <filesystem>
#include <string>

#include "sweep_file.hpp"

namespace {

namespace cli = clothlab::cli;
namespace sweep = clothlab::sweep;

std::filesystem::path scratch_base(const std::string& name) {
  const auto folder = std::filesystem::temp_directory_path() /
                      ("clothlab-sweep-bench-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  return folder / name;
}

void remove_scratch() {
  std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                              ("clothlab-sweep-bench-" + std::to_string(::getpid())));
}

// BM_SweepPerCase runs first: a fork copies the parent's page tables, so the memory the store
// benchmarks leave behind in the heap would otherwise be charged to the worker's start.
std::vector<sweep::CaseSpec> trivial_cases(std::size_t count) {
  std::string values;
  for (std::size_t i = 0; i < count; ++i) values += (i ? ", " : "") + std::to_string(i + 1);
  return sweep::expand_cases(cli::parse_sweep(
      "steps: 1\ndt: 0.001\nsweep:\n  name: overhead\n  matrix:\n    integrator: [euler]\n"
      "    scenario.seed: [" +
          values + "]\n",
      "overhead.yaml"));
}

void BM_SweepPerCase(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(0));
  const auto cases = trivial_cases(count);
  clothlab::process::Worker worker(
      [](const std::string&) {
        return nlohmann::json{{"stable", true}, {"steps", 1}}.dump();
      },
      {});
  const auto trivial_case = [&](const sweep::CaseSpec& c) {
    const auto outcome = worker.ask(c.key);
    sweep::CaseResult result;
    result.metrics = {{"steps", nlohmann::json::parse(outcome.answer)["steps"].get<double>()}};
    return result;
  };
  for (auto _ : state) {
    sweep::ResultsStore store(scratch_base("sweep-" + std::to_string(count)), false);
    const auto summary = sweep::run_sweep(cases, trivial_case, store, nullptr);
    benchmark::DoNotOptimize(summary.stable);
    state.counters["ms_per_case"] = summary.wall_s * 1000.0 / static_cast<double>(count);
  }
  state.counters["cases"] = static_cast<double>(count);
}
BENCHMARK(BM_SweepPerCase)
    ->Arg(250)
    ->Arg(2000)
    ->Arg(10000)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// A row shaped like a run-mode sweep's (coordinates, verdict, nine metrics).
sweep::Row typical_row(std::size_t index) {
  sweep::Row row;
  row["key"] = "integrator=rk4;scenario=flag;mesh=50x50;dt=0.001;case=" + std::to_string(index);
  row["integrator"] = "rk4";
  row["scenario"] = "flag";
  row["mesh"] = "50x50";
  row["dt"] = "0.001";
  row["status"] = "stable";
  row["stable"] = true;
  row["fail_step"] = nullptr;
  row["check"] = "";
  row["reason"] = "";
  for (const char* metric : {"steps", "sim_time_s", "wall_time_s", "ms_per_step", "ms_per_step_p90",
                             "force_evals", "springs_per_second", "real_time_factor", "threads"})
    row[metric] = 1234.5678 + static_cast<double>(index);
  row["verdict"] = "stable: all checks passed";
  return row;
}

void BM_StoreAppend(benchmark::State& state) {
  const auto held = static_cast<std::size_t>(state.range(0));
  sweep::ResultsStore store(scratch_base("append-" + std::to_string(held)), false);
  for (std::size_t i = 0; i < held; ++i) store.append(typical_row(i), i);
  std::size_t next = held;
  for (auto _ : state) {
    store.append(typical_row(next), next);
    ++next;
  }
  state.counters["rows_at_start"] = static_cast<double>(held);
}
BENCHMARK(BM_StoreAppend)->Arg(0)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  remove_scratch();
  return 0;
}
