// The cost of a spring on the grid's fast paths against the general (spring-list) paths a mesh
// takes (issue 34): the bench-300 flag on its grid, the same grid read as a triangle mesh, and
// an irregular mesh of the same size (irregular_grid_mesh), the scene's laws on each, and the
// irregular mesh under a material (cotton's, configs/materials/cotton.yaml: each spring's ks
// from its triangles' areas, as the CLI's presets give). Springs per second of
// one damped force evaluation (springs, damping, gravity, the flag's wind; and without the
// wind), of one rk4 step (its four evaluations), of one CG product (clothlab.cg-step/1's q = A p,
// implicit_euler's CG iteration), of xpbd's sweeps and of vbd's iterations. Run by hand, short:
// --benchmark_min_time=0.2.
#include <benchmark/benchmark.h>
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/jacobian.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_material.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <memory>
#include <string>

#include "bench_setup.hpp"
#include "mesh_test_support.hpp"

namespace clothlab::bench {
namespace {

enum class Path { Grid, GridAsMesh, IrregularMesh, IrregularCotton };

// configs/materials/cotton.yaml's material.
constexpr ClothMaterial kCotton{0.15, 6129.0, 44.95, 7.845e-6, 1.0e-5};

std::unique_ptr<Cloth> make_cloth(Path path, int side, int threads, bool velocity_forces,
                                  bool wind = true) {
  Scene scene = make_scene("flag", bench_cloth_params(side));  // bench-300's material
  if (!wind) scene.wind_strength = 0;
  PipelineOptions options{velocity_forces, threads};
  options.adaptive_threads = false;
  if (path == Path::Grid) return std::make_unique<Cloth>(scene, Precision::Float32, options);
  TriangleMesh mesh = path == Path::GridAsMesh
                          ? testing::grid_mesh(scene, testing::Diagonals::Rising)
                          : irregular_grid_mesh(scene);
  if (path == Path::IrregularCotton) {
    apply_material(scene, kCotton, &mesh);  // its mass, spread by area
    return std::make_unique<Cloth>(scene, build_mesh_model(mesh, scene, &kCotton),
                                   Precision::Float32, options);
  }
  mesh.masses.assign(std::size_t{scene.rows} * scene.cols,
                     scene.total_mass / (scene.rows * scene.cols));
  return std::make_unique<Cloth>(scene, build_mesh_model(mesh, scene), Precision::Float32, options);
}

void count_springs(benchmark::State& state, const Cloth& cloth, double passes) {
  state.counters["springs_per_s"] =
      benchmark::Counter(passes * static_cast<double>(cloth.model()->spring_count()),
                         benchmark::Counter::kIsIterationInvariantRate);
}

void evaluations(benchmark::State& state, Path path, bool wind) {
  const auto cloth = make_cloth(path, static_cast<int>(state.range(0)),
                                static_cast<int>(state.range(1)), true, wind);
  const clothlab_system& system = cloth->system();
  void* a = system.alloc_vector(system.context);
  for (auto _ : state) {
    system.eval_acceleration(system.context, 0.0, system.x, system.v, a);
    benchmark::ClobberMemory();
  }
  count_springs(state, *cloth, 1);
}

void forces(benchmark::State& state, Path path) { evaluations(state, path, true); }

// The same evaluation without the wind: the springs, their damping and gravity.
void spring_forces(benchmark::State& state, Path path) { evaluations(state, path, false); }

void rk4_step(benchmark::State& state, Path path) {
  const auto cloth =
      make_cloth(path, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), true);
  const clothlab_system& system = cloth->system();
  system.reserve_rkn(system.context, 4);
  const Cloth::RawState start = [&] {
    Cloth::RawState raw;
    cloth->copy_raw_state(raw);
    return raw;
  }();
  int steps = 0;
  for (auto _ : state) {
    system.step_rkn(system.context, 0.0, 1e-4, &testing::rk4_scheme());
    if (++steps % 1000 == 0) {  // back to rest before the flag goes anywhere odd
      state.PauseTiming();
      cloth->set_raw_state(start);
      state.ResumeTiming();
    }
  }
  count_springs(state, *cloth, 4);
}

// clothlab.cg-step/1's product q = A p at the rest state (c_x = h^2, c_v = h, damped), without
// the direction update.
void cg_products(benchmark::State& state, Path path) {
  const auto cloth =
      make_cloth(path, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), true);
  const clothlab_system& system = cloth->system();
  const auto* jacobian = static_cast<const clothlab_jacobian_extension*>(
      system.get_extension(system.context, CLOTHLAB_EXT_JACOBIAN));
  const auto* cg_step = static_cast<const clothlab_cg_step_extension*>(
      system.get_extension(system.context, CLOTHLAB_EXT_CG_STEP));
  const double h = 1e-3;
  if (jacobian == nullptr || cg_step == nullptr || jacobian->reserve(system.context) != 0 ||
      cg_step->linearise(system.context, 0.0, system.x, system.v, h * h, h) != 0) {
    state.SkipWithError("the host lacks clothlab.cg-step/1");
    return;
  }
  auto* p = static_cast<float*>(system.alloc_vector(system.context));
  void* q = system.alloc_vector(system.context);
  for (std::size_t k = 0; k < 3 * std::size_t{system.stride}; ++k)
    p[k] = 1e-3f * static_cast<float>(k % 7);
  double dot = 0;
  for (auto _ : state) {
    cg_step->product(system.context, 0.0, 0.0, nullptr, p, nullptr, q, &dot);
    benchmark::DoNotOptimize(dot);
    benchmark::ClobberMemory();
  }
  count_springs(state, *cloth, 1);
}

// Steps of an integrator whose cost is `passes` passes over the springs per step (xpbd:
// substeps x iterations sweeps; vbd: iterations sweeps over the particles' springs).
void integrator_steps(benchmark::State& state, Path path, const std::string& id,
                      const ParamTexts& params, double passes) {
  const int threads = static_cast<int>(state.range(1));
  const auto cloth = make_cloth(path, static_cast<int>(state.range(0)), threads,
                                integrator_uses_velocity_forces(id));
  ParamTexts with_threads = params;
  with_threads.emplace_back("threads", std::to_string(threads));
  BoundIntegrator integrator(id, *cloth, with_threads);
  const Cloth::RawState start = [&] {
    Cloth::RawState raw;
    cloth->copy_raw_state(raw);
    return raw;
  }();
  double t = 0;
  int steps = 0;
  for (auto _ : state) {
    integrator.step(t, 1e-3);
    t += 1e-3;
    if (++steps % 200 == 0) {
      state.PauseTiming();
      cloth->set_raw_state(start);
      state.ResumeTiming();
    }
  }
  count_springs(state, *cloth, passes);
}

void xpbd_sweeps(benchmark::State& state, Path path) {
  integrator_steps(state, path, "xpbd", {{"inner_substeps", "2"}, {"iterations", "5"}}, 10);
}

void vbd_iterations(benchmark::State& state, Path path) {
  integrator_steps(state, path, "vbd", {{"iterations", "10"}}, 10);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int threads : {1, 2}) b->Args({300, threads});
  b->ArgNames({"side", "threads"})->Unit(benchmark::kMillisecond);
}

#define CLOTHLAB_MESH_PATH_BENCH(function)                                        \
  BENCHMARK_CAPTURE(function, grid, Path::Grid)->Apply(sizes);                    \
  BENCHMARK_CAPTURE(function, grid_as_mesh, Path::GridAsMesh)->Apply(sizes);      \
  BENCHMARK_CAPTURE(function, irregular_mesh, Path::IrregularMesh)->Apply(sizes); \
  BENCHMARK_CAPTURE(function, irregular_cotton, Path::IrregularCotton)->Apply(sizes)

CLOTHLAB_MESH_PATH_BENCH(forces);
CLOTHLAB_MESH_PATH_BENCH(spring_forces);
CLOTHLAB_MESH_PATH_BENCH(rk4_step);
CLOTHLAB_MESH_PATH_BENCH(cg_products);
CLOTHLAB_MESH_PATH_BENCH(xpbd_sweeps);
CLOTHLAB_MESH_PATH_BENCH(vbd_iterations);

}  // namespace
}  // namespace clothlab::bench

BENCHMARK_MAIN();
