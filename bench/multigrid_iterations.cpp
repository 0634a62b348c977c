// CG iterations of implicit_euler's linear solve with the multigrid and the block-Jacobi
// preconditioner (preconditioned_cg.hpp, the plugin's own code) on the cotton flag's backward-
// Euler system, at several mesh sizes and time steps: the resolution-independence table of
// lab/real-cloth.md ("Multigrid"). The system is the first step's: the flag at rest in its
// initial layout, the definite Jacobian (the plugin's default), right-hand side h a0, solved
// from 0 to a relative residual (mass norm) of 1e-6 in float64, the multigrid with the
// plugin's default coarsest level and sweeps.
//
//   build/bin/clothlab_multigrid_iterations [config [side...] [--rate N...]] [--split]
//
// --split prints, for the multigrid alone, where a solve's time goes instead: the set-up (the
// preconditioner's build in CG's start: 75 probing products, then the Galerkin products and
// factors, whose share is the set-up less 75 products timed on their own) against the
// iterations (one product and one V-cycle each), and the set-up in iterations.
//
// config (default configs/choose-cotton-flag-200.yaml) gives the material and scenario; sides
// default to 50 100 200 300 600, the steps h = 1/N s to N = 60 and 240. One thread: the counts do
// not depend on it, and the times (whole solves, set-up included) are then comparable on a shared
// machine. Block-Jacobi stops at 3000 iterations and is then reported as not converged, with the
// residual it reached.
#include <chrono>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/sdk.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
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

struct SolveResult {
  long iterations = 0;
  bool converged = false;
  double relative_residual = 0.0;
  double seconds = 0.0;          // the whole solve: set-up (preconditioner) and iterations
  double setup_seconds = 0.0;    // CG's start: the preconditioner's build and first residual
  double probing_seconds = 0.0;  // 75 Jacobian products, the probing's share of the set-up
};

constexpr int kProbingProducts = 75;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Solves the first backward-Euler system of `cloth` at step h with one preconditioner.
SolveResult solve(const Cloth& cloth, double h, bool multigrid, long cap) {
  const sdk::System<double> system(cloth.system());
  system.jacobian().reserve();
  std::array<double*, builtin::PreconditionedCg<double>::vector_count> vectors{};
  for (double*& vector : vectors) vector = system.alloc_vector();
  double* const rhs = system.alloc_vector();
  double* const solution = system.alloc_vector();
  double* const zero = system.alloc_vector();
  std::vector<double> inverse_blocks(9 * std::size_t{system.particle_count()});
  std::optional<builtin::MultigridPreconditioner> preconditioner;
  if (multigrid)
    preconditioner.emplace(system, builtin::kDefaultCoarsestNodes,
                           builtin::kDefaultMultigridSweeps);
  builtin::PreconditionedCg<double> cg(system, vectors, inverse_blocks, true, false,
                                       preconditioner ? &*preconditioner : nullptr);
  system.acceleration(0.0, system.x(), system.v(), rhs);
  system.template lincomb<1>(rhs, zero, {h}, {rhs});
  system.copy(solution, zero);

  SolveResult result;
  const auto start = std::chrono::steady_clock::now();
  cg.start(0.0, h, system.x(), system.v(), rhs, solution, false, kTolerance);
  result.setup_seconds = seconds_since(start);
  result.converged = cg.converged();
  while (!result.converged && result.iterations < cap) {
    const auto outcome = cg.iterate();
    if (outcome == builtin::PreconditionedCg<double>::Outcome::kBreakdown) break;
    ++result.iterations;
    result.converged = outcome == builtin::PreconditionedCg<double>::Outcome::kConverged;
  }
  cg.finish();
  result.seconds = seconds_since(start);
  result.relative_residual = cg.residual_norm() / cg.rhs_norm();
  const auto probing_start = std::chrono::steady_clock::now();
  for (int k = 0; k < kProbingProducts; ++k)
    system.definite_jacobian().apply(0.0, system.x(), system.v(), -h * h, -h, rhs, solution);
  result.probing_seconds = seconds_since(probing_start);
  return result;
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

int print_split(const cli::RunConfig& config, const std::vector<int>& sides,
                const std::vector<int>& rates) {
  std::printf(
      "| side | h (s) | set-up ms | of which probing ms | Galerkin + factors ms | iterations | "
      "iterations ms | ms per iteration | set-up in iterations |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (const int rate : rates)
    for (const int side : sides) {
      const Scene scene = make_material_scene(config, side);
      const Cloth cloth(scene, Precision::Float64, PipelineOptions{true, 1});
      const SolveResult r = solve(cloth, 1.0 / rate, true, kMultigridCap);
      const double iterating = r.seconds - r.setup_seconds;
      const double per_iteration = iterating / static_cast<double>(std::max(r.iterations, 1L));
      std::printf("| %d | 1/%d | %.1f | %.1f | %.1f | %ld%s | %.1f | %.2f | %.1f |\n", side, rate,
                  1e3 * r.setup_seconds, 1e3 * r.probing_seconds,
                  1e3 * (r.setup_seconds - r.probing_seconds), r.iterations,
                  r.converged ? "" : " (not converged)", 1e3 * iterating, 1e3 * per_iteration,
                  r.setup_seconds / per_iteration);
      std::fflush(stdout);
    }
  return 0;
}

int run(int argc, char** argv) {
  const std::string config_path = argc > 1 ? argv[1] : "configs/choose-cotton-flag-200.yaml";
  std::vector<int> sides, rates;
  bool reading_rates = false, split = false;
  for (int k = 2; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--split") {
      split = true;
      continue;
    }
    if (arg == "--rate") {
      reading_rates = true;
      continue;
    }
    const int value = std::atoi(arg.c_str());
    if (value <= 0) {
      std::fprintf(stderr, "clothlab_multigrid_iterations: '%s' is no positive integer\n",
                   arg.c_str());
      return 2;
    }
    (reading_rates ? rates : sides).push_back(value);
  }
  if (sides.empty()) sides = {50, 100, 200, 300, 600};
  if (rates.empty()) rates = {60, 240};
  const cli::RunConfig config = cli::resolve_run_config(config::read_config_file(config_path));
  if (!config.material) {
    std::fprintf(stderr, "%s: no material.* (the table is for a material's cloth)\n",
                 config_path.c_str());
    return 2;
  }
  std::printf("%s, %s scenario, float64, 1 thread, CG from 0 to a relative residual of %g\n\n",
              config.material->name.c_str(), config.scenario.c_str(), kTolerance);
  if (split) return print_split(config, sides, rates);
  std::printf(
      "| side | h (s) | multigrid levels | multigrid iterations | s | block-Jacobi "
      "iterations | s |\n|---|---|---|---|---|---|---|\n");
  for (const int rate : rates) {
    const double h = 1.0 / rate;
    long fewest = 0, most = 0;
    for (const int side : sides) {
      const Scene scene = make_material_scene(config, side);
      const Cloth cloth(scene, Precision::Float64, PipelineOptions{true, 1});
      const SolveResult multigrid = solve(cloth, h, true, kMultigridCap);
      const SolveResult block_jacobi = solve(cloth, h, false, kBlockJacobiCap);
      const std::size_t levels =
          builtin::plan_levels(static_cast<uint32_t>(side), static_cast<uint32_t>(side),
                               builtin::kDefaultCoarsestNodes)
              .size();
      std::printf("| %d | 1/%.0f | %zu | %s | %s |\n", side, 1.0 / h, levels,
                  describe(multigrid).c_str(), describe(block_jacobi).c_str());
      std::fflush(stdout);
      fewest = fewest == 0 ? multigrid.iterations : std::min(fewest, multigrid.iterations);
      most = std::max(most, multigrid.iterations);
    }
    std::printf("| | | | max/min %.2f over the sides | | | |\n",
                static_cast<double>(most) / static_cast<double>(std::max(fewest, 1L)));
  }
  return 0;
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
