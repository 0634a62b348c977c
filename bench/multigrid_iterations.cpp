// CG iterations of implicit_euler's linear solve with the multigrid and the block-Jacobi
// preconditioner (preconditioned_cg.hpp, the plugin's own code) on the cotton flag's backward-
// Euler system, at several mesh sizes and time steps: the resolution-independence table of
// lab/real-cloth.md ("Multigrid"). The system is the first step's: the flag at rest in its
// initial layout, the definite Jacobian (the plugin's default), right-hand side h a0, solved
// from 0 to a relative residual (mass norm) of 1e-6, the multigrid with the plugin's default
// coarsest level and sweeps.
//
//   build/bin/clothlab_multigrid_iterations [config [side...] [--rate N...]
//       [--threads N...] [--precision float32|float64] [--assembly table|probe]
//       [--sweeps N] [--split] [--cpu]]
//
// --assembly: where the multigrid's fine blocks come from, the host's block table
// (clothlab.definite-jacobian/2, the plugin's choice, default) or 75 probing products.
// --sweeps: the V-cycle's smoothing steps each side on every level (implicit_euler's
// `multigrid_sweeps`; default its default).
// --split prints, for the multigrid alone, where a solve's time goes instead: the set-up (the
// preconditioner's build in CG's start: the fine blocks, then the Galerkin products and
// factors, whose share is the set-up less the fine blocks' call or products timed on their
// own) against the
// iterations (one product and one V-cycle each), the set-up in iterations, and an iteration in
// explicit euler steps of the same cloth at the same precision and thread count (the euler
// plugin's step, timed on its own). Its times are the fastest of 3 solves and of 5 batches of
// 10 euler steps. --cpu times with the process's CPU time instead of the wall clock: on a
// machine shared with other work a one-thread row then counts only this process's cycles
// (with several threads it sums theirs, so compare those rows at equal thread counts only).
//
// config (default configs/choose-cotton-flag-200.yaml) gives the material and scenario; sides
// default to 50 100 200 300 600, the steps h = 1/N s to N = 60 and 240, the threads to 1 and the
// precision to float64. Times are whole solves, set-up included. Block-Jacobi stops at 3000
// iterations and is then reported as not converged, with the residual it reached.
#include <algorithm>
#include <array>
#include <chrono>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/sdk.hpp>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_setup.hpp"
#include "material_scene.hpp"
#include "preconditioned_cg.hpp"
#include "run_config.hpp"

namespace clothlab::bench {
namespace {

constexpr double kTolerance = 1e-6;
constexpr long kBlockJacobiCap = 3000;
constexpr long kMultigridCap = 500;
// Times are the fastest of a few runs: on a shared machine the others only add waits.
constexpr int kSolveRuns = 3;
constexpr int kEulerBatches = 5, kEulerStepsPerBatch = 10;

struct SolveResult {
  long iterations = 0;
  bool converged = false;
  double relative_residual = 0.0;
  double seconds = 0.0;              // the whole solve: set-up (preconditioner) and iterations
  double setup_seconds = 0.0;        // CG's start: the preconditioner's build and first residual
  double fine_blocks_seconds = 0.0;  // the block table's call or the 75 probing products
};

constexpr int kProbingProducts = 75;

// Whether the multigrid takes the host's block table (--assembly table) or probes.
bool use_block_table = true;

// The V-cycle's smoothing steps each side (--sweeps).
long multigrid_sweeps = builtin::kDefaultMultigridSweeps;

// The clock every time is read from: the wall clock, or the process's CPU time (--cpu).
bool use_cpu_time = false;

double now_seconds() {
  if (use_cpu_time) {
    timespec cpu{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu);
    return static_cast<double>(cpu.tv_sec) + 1e-9 * static_cast<double>(cpu.tv_nsec);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double seconds_since(double start) { return now_seconds() - start; }

// Solves the first backward-Euler system of `cloth` at step h with one preconditioner.
template <class Real>
SolveResult solve(const Cloth& cloth, double h, bool multigrid, long cap) {
  const sdk::System<Real> system(cloth.system());
  system.jacobian().reserve();
  std::array<Real*, builtin::PreconditionedCg<Real>::vector_count> vectors{};
  for (Real*& vector : vectors) vector = system.alloc_vector();
  Real* const rhs = system.alloc_vector();
  Real* const solution = system.alloc_vector();
  Real* const zero = system.alloc_vector();
  std::vector<double> inverse_blocks(9 * std::size_t{system.particle_count()});
  std::optional<builtin::MultigridPreconditioner> preconditioner;
  const bool table = use_block_table && system.definite_jacobian().has_blocks();
  if (multigrid)
    preconditioner.emplace(system, builtin::kDefaultCoarsestNodes, multigrid_sweeps, 1,
                           table ? std::optional(system.jacobian().pattern()) : std::nullopt);
  std::vector<double> block_values(table ? 9 * std::size_t{system.jacobian().pattern().block_count}
                                         : 0);
  builtin::PreconditionedCg<Real> cg(system, vectors, inverse_blocks, true, true,
                                     preconditioner ? &*preconditioner : nullptr);
  system.acceleration(0.0, system.x(), system.v(), rhs);
  system.template lincomb<1>(rhs, zero, {h}, {rhs});
  system.copy(solution, zero);

  SolveResult result;
  const double start = now_seconds();
  cg.start(0.0, h, system.x(), system.v(), rhs, solution, false, kTolerance);
  result.setup_seconds = seconds_since(start);
  result.converged = cg.converged();
  while (!result.converged && result.iterations < cap) {
    const auto outcome = cg.iterate();
    if (outcome == builtin::PreconditionedCg<Real>::Outcome::kBreakdown) break;
    ++result.iterations;
    result.converged = outcome == builtin::PreconditionedCg<Real>::Outcome::kConverged;
  }
  cg.finish();
  result.seconds = seconds_since(start);
  result.relative_residual = cg.residual_norm() / cg.rhs_norm();
  const double fine_blocks_start = now_seconds();
  if (table) {
    system.definite_jacobian().blocks(0.0, system.x(), system.v(), -h * h, -h, block_values.data());
  } else {
    for (int k = 0; k < kProbingProducts; ++k)
      system.definite_jacobian().apply(0.0, system.x(), system.v(), -h * h, -h, rhs, solution);
  }
  result.fine_blocks_seconds = seconds_since(fine_blocks_start);
  return result;
}

SolveResult solve(const Cloth& cloth, double h, bool multigrid, long cap) {
  return cloth.precision() == Precision::Float32 ? solve<float>(cloth, h, multigrid, cap)
                                                 : solve<double>(cloth, h, multigrid, cap);
}

// The multigrid solve of the fastest of kSolveRuns.
SolveResult fastest_multigrid_solve(const Cloth& cloth, double h) {
  SolveResult best = solve(cloth, h, true, kMultigridCap);
  for (int run = 1; run < kSolveRuns; ++run) {
    const SolveResult next = solve(cloth, h, true, kMultigridCap);
    if (next.seconds < best.seconds) best = next;
  }
  return best;
}

// Seconds per step of the euler plugin on the scene (from rest, at a step too short to matter
// for its cost): the mean of the fastest batch of steps, after one untimed step.
double euler_step_seconds(const Scene& scene, Precision precision, int threads) {
  const Cloth cloth(scene, precision, PipelineOptions{true, threads});
  BoundIntegrator euler("euler", cloth);
  const double dt = 1e-5;
  double t = 0.0, fastest = 0.0;
  euler.step(t, dt);
  for (int batch = 0; batch < kEulerBatches; ++batch) {
    const double start = now_seconds();
    for (int k = 0; k < kEulerStepsPerBatch; ++k) euler.step(t += dt, dt);
    const double seconds = seconds_since(start);
    fastest = batch == 0 ? seconds : std::min(fastest, seconds);
  }
  return fastest / kEulerStepsPerBatch;
}

std::string describe(const SolveResult& result) {
  char text[96];
  if (result.converged) {
    std::snprintf(text, sizeof text, "%ld | %.3g", result.iterations, result.seconds);
  } else {
    std::snprintf(text, sizeof text, "did not converge (%ld, residual %.1e) | %.3g",
                  result.iterations, result.relative_residual, result.seconds);
  }
  return text;
}

struct Options {
  std::vector<int> sides, rates, threads;
  Precision precision = Precision::Float64;
  bool split = false;
  bool cpu = false;
  bool assembly_table = true;
  long sweeps = builtin::kDefaultMultigridSweeps;
};

int print_split(const cli::RunConfig& config, const Options& options) {
  std::printf(
      "| side | threads | h (s) | set-up ms | of which fine blocks ms | Galerkin + factors ms | "
      "iterations | iterations ms | ms per iteration | set-up in iterations | euler step ms | "
      "iteration in euler steps |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const int rate : options.rates)
    for (const int side : options.sides)
      for (const int threads : options.threads) {
        const Scene scene = make_material_scene(config, side);
        const Cloth cloth(scene, options.precision, PipelineOptions{true, threads});
        const SolveResult r = fastest_multigrid_solve(cloth, 1.0 / rate);
        const double euler = euler_step_seconds(scene, options.precision, threads);
        const double iterating = r.seconds - r.setup_seconds;
        const double per_iteration = iterating / static_cast<double>(std::max(r.iterations, 1L));
        std::printf(
            "| %d | %d | 1/%d | %.1f | %.1f | %.1f | %ld%s | %.1f | %.2f | %.1f | %.3f | %.1f |\n",
            side, threads, rate, 1e3 * r.setup_seconds, 1e3 * r.fine_blocks_seconds,
            1e3 * (r.setup_seconds - r.fine_blocks_seconds), r.iterations,
            r.converged ? "" : " (not converged)", 1e3 * iterating, 1e3 * per_iteration,
            r.setup_seconds / per_iteration, 1e3 * euler, per_iteration / euler);
        std::fflush(stdout);
      }
  return 0;
}

int print_iterations(const cli::RunConfig& config, const Options& options) {
  std::printf(
      "| side | threads | h (s) | multigrid levels | multigrid iterations | s | block-Jacobi "
      "iterations | s |\n|---|---|---|---|---|---|---|---|\n");
  for (const int rate : options.rates) {
    const double h = 1.0 / rate;
    long fewest = 0, most = 0;
    for (const int side : options.sides)
      for (const int threads : options.threads) {
        const Scene scene = make_material_scene(config, side);
        const Cloth cloth(scene, options.precision, PipelineOptions{true, threads});
        const SolveResult multigrid = solve(cloth, h, true, kMultigridCap);
        const SolveResult block_jacobi = solve(cloth, h, false, kBlockJacobiCap);
        const std::size_t levels =
            builtin::plan_levels(static_cast<uint32_t>(side), static_cast<uint32_t>(side),
                                 builtin::kDefaultCoarsestNodes, builtin::kPreconditionerCoarsening)
                .size();
        std::printf("| %d | %d | 1/%.0f | %zu | %s | %s |\n", side, threads, 1.0 / h, levels,
                    describe(multigrid).c_str(), describe(block_jacobi).c_str());
        std::fflush(stdout);
        fewest = fewest == 0 ? multigrid.iterations : std::min(fewest, multigrid.iterations);
        most = std::max(most, multigrid.iterations);
      }
    std::printf("| | | | | max/min %.2f over the sides | | | |\n",
                static_cast<double>(most) / static_cast<double>(std::max(fewest, 1L)));
  }
  return 0;
}

// The options after the config; a one-line std::runtime_error naming a bad one.
Options parse_options(int argc, char** argv) {
  Options options;
  std::vector<int>* list = &options.sides;
  for (int k = 2; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--split") {
      options.split = true;
    } else if (arg == "--cpu") {
      options.cpu = true;
    } else if (arg == "--rate") {
      list = &options.rates;
    } else if (arg == "--threads") {
      list = &options.threads;
    } else if (arg == "--assembly") {
      const std::string value = k + 1 < argc ? argv[++k] : "";
      if (value != "table" && value != "probe")
        throw std::runtime_error("--assembly '" + value + "': table or probe");
      options.assembly_table = value == "table";
    } else if (arg == "--sweeps") {
      const std::string value = k + 1 < argc ? argv[++k] : "";
      const double sweeps = number_of("--sweeps", value.c_str());
      if (sweeps < 1 || sweeps > 8 || sweeps != static_cast<long>(sweeps))
        throw std::runtime_error("--sweeps '" + value + "': an integer in [1, 8]");
      options.sweeps = static_cast<long>(sweeps);
    } else if (arg == "--precision") {
      const std::string value = k + 1 < argc ? argv[++k] : "";
      if (value != "float32" && value != "float64")
        throw std::runtime_error("--precision '" + value + "': float32 or float64");
      options.precision = value == "float32" ? Precision::Float32 : Precision::Float64;
    } else {
      const double value = number_of(list == &options.sides   ? "side"
                                     : list == &options.rates ? "--rate"
                                                              : "--threads",
                                     arg.c_str());
      if (value < 1 || value > 100000 || value != static_cast<int>(value))
        throw std::runtime_error("'" + arg + "' is no integer in [1, 100000]");
      list->push_back(static_cast<int>(value));
    }
  }
  if (options.sides.empty()) options.sides = {50, 100, 200, 300, 600};
  if (options.rates.empty()) options.rates = {60, 240};
  if (options.threads.empty()) options.threads = {1};
  return options;
}

int run(int argc, char** argv) {
  const std::string config_path = argc > 1 ? argv[1] : "configs/choose-cotton-flag-200.yaml";
  const Options options = parse_options(argc, argv);
  use_cpu_time = options.cpu;
  use_block_table = options.assembly_table;
  multigrid_sweeps = options.sweeps;
  const cli::RunConfig config = cli::resolve_run_config(config::read_config_file(config_path));
  if (!config.material) {
    std::fprintf(stderr, "%s: no material.* (the table is for a material's cloth)\n",
                 config_path.c_str());
    return 2;
  }
  std::printf(
      "%s, %s scenario, %s, CG from 0 to a relative residual of %g, %s, fine blocks %s, %ld "
      "smoothing steps each side\n\n",
      config.material->name.c_str(), config.scenario.c_str(), to_string(options.precision),
      kTolerance, options.cpu ? "CPU time of the process" : "wall-clock time",
      options.assembly_table ? "from the host's block table" : "by probing", options.sweeps);
  return options.split ? print_split(config, options) : print_iterations(config, options);
}

}  // namespace
}  // namespace clothlab::bench

int main(int argc, char** argv) {
  try {
    return clothlab::bench::run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "clothlab_multigrid_iterations: %s\n", error.what());
    return 1;
  }
}
