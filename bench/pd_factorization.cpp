// projective_dynamics' three global solves of its constant matrix M + h D + h^2 K (parameter
// `factorization`): Eigen's SimplicialLDLT, SuiteSparse CHOLMOD's supernodal LL^T and the
// multigrid V-cycles (no factorisation), on the cotton flag of
// configs/choose-cotton-flag-200.yaml at 100^2, 200^2 and 300^2 particles, h = 1/60 s, with the
// plugin's own matrix (projective_dynamics_matrix.hpp: AMD order for the factorisations,
// particle order for the multigrid) and solver headers. Per size and solve: the setup a step
// pays when h changes (the numeric factorisation, or the multigrid's Galerkin levels, smoother
// blocks and coarsest Cholesky; the symbolic analysis and the hierarchy's storage are
// prepare's), one solve of the three coordinates (what each local/global iteration pays; the
// multigrid's from zero to a 1e-6 relative residual, the most a warm-started solve can take)
// and the bytes kept between solves; CHOLMOD's own peak allocation beside them. Run by hand from
// the repository root (lab/performance.md):
//   build/bin/clothlab_pd_factorization --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <algorithm>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/sdk.hpp>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "bench_setup.hpp"
#include "cholmod_factorization.hpp"
#include "material_scene.hpp"
#include "multigrid_global_solve.hpp"
#include "projective_dynamics_matrix.hpp"
#include "run_config.hpp"
#include "simplicial_ldlt_factorization.hpp"

namespace clothlab::bench {
namespace {

constexpr const char* kConfig = "configs/choose-cotton-flag-200.yaml";
constexpr double kStep = 1.0 / 60.0;

using Order = builtin::ProjectiveDynamicsMatrix::Order;

// The cotton flag's matrix at side x side particles, and its grid: per unknown, its particle
// (the grid node r * side + c); per particle, 1 where pinned.
struct FlagMatrix {
  builtin::ProjectiveDynamicsMatrix::Matrix matrix;
  std::vector<uint32_t> node_of;
  std::vector<uint8_t> fixed;
};

// Built once per size and order.
const FlagMatrix& flag(int side, Order order) {
  static std::map<std::pair<int, Order>, FlagMatrix> built;
  auto found = built.find({side, order});
  if (found != built.end()) return found->second;
  const cli::RunConfig config = cli::resolve_run_config(config::read_config_file(kConfig));
  if (!config.material) throw std::runtime_error(std::string(kConfig) + ": no material");
  const Scene scene = make_material_scene(config, side);
  const Cloth cloth(scene, Precision::Float64, PipelineOptions{true, 1});
  const sdk::System<double> system(cloth.system());
  builtin::ProjectiveDynamicsMatrix matrix;
  matrix.build(system, system.topology(), order);
  FlagMatrix out{matrix.pattern(), matrix.node_of(),
                 std::vector<uint8_t>(matrix.unknown_of().size(), 1)};
  matrix.combine(kStep, out.matrix);
  for (const uint32_t node : out.node_of) out.fixed[node] = 0;
  return built.emplace(std::pair{side, order}, std::move(out)).first->second;
}

const builtin::ProjectiveDynamicsMatrix::Matrix& flag_matrix(int side) {
  return flag(side, Order::kFillReducing).matrix;
}

// The multigrid solve of the plugin's defaults (multigrid_coarsest, multigrid_sweeps), to a
// 1e-6 relative residual, on the flag's matrix in particle order; one thread, as the
// simplicial factorisation's solves.
class Multigrid {
 public:
  explicit Multigrid(int side)
      : flag_(flag(side, Order::kParticles)),
        solve_(builtin::plan_levels(static_cast<uint32_t>(side), static_cast<uint32_t>(side),
                                    builtin::kDefaultCoarsestNodes),
               flag_.fixed, flag_.node_of, builtin::kDefaultMultigridSweeps, 1e-6,
               builtin::kDefaultGlobalSolveMaxCycles, 1),
        guess_(3 * flag_.node_of.size(), 0.0),
        origin_(guess_.size(), 0.0) {}
  const builtin::ProjectiveDynamicsMatrix::Matrix& matrix() const { return flag_.matrix; }
  std::string factorize() { return solve_.factorize(flag_.matrix); }
  // x = A^-1 x from zero; the cycles it took.
  long solve_in_place(double* x) {
    std::fill(guess_.begin(), guess_.end(), 0.0);
    const builtin::MultigridGlobalSolve::Outcome outcome =
        solve_.solve(x, origin_.data(), guess_.data());
    std::copy(guess_.begin(), guess_.end(), x);
    return outcome.converged ? outcome.cycles : -1;
  }
  std::size_t storage_bytes() const { return solve_.storage_bytes(); }

 private:
  const FlagMatrix& flag_;
  builtin::MultigridGlobalSolve solve_;
  std::vector<double> guess_, origin_;
};

template <class Factorization>
void report_memory(benchmark::State& state, const Factorization& factorization) {
  if constexpr (std::is_same_v<Factorization, Multigrid>) {
    state.counters["factor_MB"] = static_cast<double>(factorization.storage_bytes()) / 1e6;
  } else {
    state.counters["factor_MB"] = static_cast<double>(factorization.factor_bytes()) / 1e6;
  }
  if constexpr (std::is_same_v<Factorization, builtin::CholmodFactorization>)
    state.counters["cholmod_peak_MB"] = static_cast<double>(factorization.peak_bytes()) / 1e6;
}

// The setup per step size: multigrid's hierarchy, or a factorisation after its analysis.
void MultigridSetup(benchmark::State& state) {
  Multigrid multigrid(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const std::string failure = multigrid.factorize();
    if (!failure.empty()) state.SkipWithError(failure.c_str());
  }
  state.counters["unknowns"] = static_cast<double>(multigrid.matrix().rows());
  report_memory(state, multigrid);
}

void MultigridSolve(benchmark::State& state) {
  Multigrid multigrid(static_cast<int>(state.range(0)));
  const std::string failure = multigrid.factorize();
  if (!failure.empty()) state.SkipWithError(failure.c_str());
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> rhs(3 * static_cast<size_t>(multigrid.matrix().rows())), x(rhs.size());
  for (double& value : rhs) value = uniform(random);
  long cycles = 0;
  for (auto _ : state) {
    std::copy(rhs.begin(), rhs.end(), x.begin());
    cycles = multigrid.solve_in_place(x.data());
    if (cycles < 0) state.SkipWithError("the multigrid missed 1e-6");
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["cycles"] = static_cast<double>(cycles);
  report_memory(state, multigrid);
}

template <class Factorization>
void Factor(benchmark::State& state) {
  const auto& matrix = flag_matrix(static_cast<int>(state.range(0)));
  Factorization factorization;
  factorization.analyze(matrix);
  for (auto _ : state) {
    const std::string failure = factorization.factorize(matrix);
    if (!failure.empty()) state.SkipWithError(failure.c_str());
  }
  state.counters["unknowns"] = static_cast<double>(matrix.rows());
  report_memory(state, factorization);
}

template <class Factorization>
void Solve(benchmark::State& state) {
  const auto& matrix = flag_matrix(static_cast<int>(state.range(0)));
  Factorization factorization;
  factorization.analyze(matrix);
  const std::string failure = factorization.factorize(matrix);
  if (!failure.empty()) state.SkipWithError(failure.c_str());
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> rhs(3 * static_cast<size_t>(matrix.rows())), x(rhs.size());
  for (double& value : rhs) value = uniform(random);
  for (auto _ : state) {
    std::copy(rhs.begin(), rhs.end(), x.begin());  // a fresh right-hand side each time
    factorization.solve_in_place(x.data());
    benchmark::DoNotOptimize(x.data());
  }
  report_memory(state, factorization);
}

using Ldlt = builtin::SimplicialLdltFactorization;
using Cholmod = builtin::CholmodFactorization;
// The flag sides every benchmark here runs, timed alike.
void on_flag_sides(benchmark::internal::Benchmark* runs) {
  runs->Arg(100)->Arg(200)->Arg(300)->Unit(benchmark::kMillisecond);
  runs->MeasureProcessCPUTime()->UseRealTime();
}

BENCHMARK(Factor<Ldlt>)->Apply(on_flag_sides);
BENCHMARK(Factor<Cholmod>)->Apply(on_flag_sides);
BENCHMARK(Solve<Ldlt>)->Apply(on_flag_sides);
BENCHMARK(Solve<Cholmod>)->Apply(on_flag_sides);
BENCHMARK(MultigridSetup)->Apply(on_flag_sides);
BENCHMARK(MultigridSolve)->Apply(on_flag_sides);

}  // namespace
}  // namespace clothlab::bench

BENCHMARK_MAIN();
