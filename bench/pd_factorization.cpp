// projective_dynamics' two factorisations of its constant matrix M + h D + h^2 K (parameter
// `factorization`): Eigen's SimplicialLDLT and SuiteSparse CHOLMOD's supernodal LL^T, on the
// cotton flag of configs/choose-cotton-flag-200.yaml at 100^2, 200^2 and 300^2 particles,
// h = 1/60 s, with the plugin's own matrix (projective_dynamics_matrix.hpp, AMD order) and
// factorisation headers. Per size and factorisation: the numeric factorisation (what a step
// pays when h changes; the symbolic analysis is prepare's), one solve of the three coordinates
// (what each local/global iteration pays) and the factor's bytes; CHOLMOD's own peak
// allocation beside them. Run by hand from the repository root (docs/performance.md):
//   build/bin/clothlab_pd_factorization --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <algorithm>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/core/cloth.hpp>
#include <clothlab/sdk.hpp>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "bench_setup.hpp"
#include "cholmod_factorization.hpp"
#include "material.hpp"
#include "projective_dynamics_matrix.hpp"
#include "run_config.hpp"
#include "simplicial_ldlt_factorization.hpp"

namespace clothlab::bench {
namespace {

constexpr const char* kConfig = "configs/choose-cotton-flag-200.yaml";
constexpr double kStep = 1.0 / 60.0;

// The cotton flag's matrix at side x side particles, built once per size.
const builtin::ProjectiveDynamicsMatrix::Matrix& flag_matrix(int side) {
  static std::map<int, builtin::ProjectiveDynamicsMatrix::Matrix> built;
  auto found = built.find(side);
  if (found != built.end()) return found->second;
  const cli::RunConfig config = cli::resolve_run_config(config::read_config_file(kConfig));
  if (!config.material) throw std::runtime_error(std::string(kConfig) + ": no material");
  const Scene scene = make_scene(config.scenario, [&](host::ParamSet& values) {
    values.set("rows", std::to_string(side), "bench");
    values.set("cols", std::to_string(side), "bench");
    cli::apply_material(*config.material, {}, values);
  });
  const Cloth cloth(scene, Precision::Float64, PipelineOptions{true, 1});
  const sdk::System<double> system(cloth.system());
  builtin::ProjectiveDynamicsMatrix matrix;
  matrix.build(system, system.topology());
  builtin::ProjectiveDynamicsMatrix::Matrix combined = matrix.pattern();
  matrix.combine(kStep, combined);
  return built.emplace(side, std::move(combined)).first->second;
}

template <class Factorization>
void report_memory(benchmark::State& state, const Factorization& factorization) {
  state.counters["factor_MB"] = static_cast<double>(factorization.factor_bytes()) / 1e6;
  if constexpr (std::is_same_v<Factorization, builtin::CholmodFactorization>)
    state.counters["cholmod_peak_MB"] = static_cast<double>(factorization.peak_bytes()) / 1e6;
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
BENCHMARK(Factor<Ldlt>)
    ->Arg(100)
    ->Arg(200)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(Factor<Cholmod>)
    ->Arg(100)
    ->Arg(200)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(Solve<Ldlt>)
    ->Arg(100)
    ->Arg(200)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(Solve<Cholmod>)
    ->Arg(100)
    ->Arg(200)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace clothlab::bench

BENCHMARK_MAIN();
