// The engine's two force paths (issue 34): the grid's row pipeline against the spring-list path
// a mesh takes (PipelineOptions::force_general_path on the same grid), and the spring-list path
// on an irregular mesh of about the same size; springs per second of one damped force
// evaluation (springs, damping, gravity, the flag's wind) and of one rk4 step (its four
// evaluations). Run by hand, short: --benchmark_min_time=0.2.
#include <benchmark/benchmark.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <memory>

#include "bench_setup.hpp"

namespace clothlab::bench {
namespace {

// A side x side sheet of unit spacing, each vertex moved by up to a quarter of the spacing and
// each cell split along a diagonal chosen by a hash (no rectangles, no straight lines).
TriangleMesh irregular_sheet(uint32_t side, double width) {
  TriangleMesh mesh;
  auto hash = [](uint32_t value) {
    value ^= value >> 16;
    value *= 0x7feb352dU;
    value ^= value >> 15;
    value *= 0x846ca68bU;
    return value ^ (value >> 16);
  };
  auto jitter = [&](uint32_t i, uint32_t k) {
    return (static_cast<double>(hash(3 * i + k) % 1000) / 1000.0 - 0.5) * 0.5;
  };
  const double spacing = width / (side - 1);
  for (uint32_t r = 0; r < side; ++r)
    for (uint32_t c = 0; c < side; ++c) {
      const uint32_t i = r * side + c;
      mesh.positions.insert(mesh.positions.end(),
                            {(c + jitter(i, 0)) * spacing, 1.0 - (r + jitter(i, 1)) * spacing,
                             0.2 * jitter(i, 2) * spacing});
    }
  for (uint32_t r = 0; r + 1 < side; ++r)
    for (uint32_t c = 0; c + 1 < side; ++c) {
      const uint32_t a = r * side + c, b = a + 1, below = a + side, d = below + 1;
      if (hash(a + 7919) % 2 == 0)
        mesh.triangles.insert(mesh.triangles.end(), {a, b, d, a, d, below});
      else
        mesh.triangles.insert(mesh.triangles.end(), {a, below, b, b, below, d});
    }
  return mesh;
}

enum class Path { Grid, GeneralOnGrid, IrregularMesh };

std::unique_ptr<Cloth> make_cloth(Path path, int side, int threads) {
  const Scene scene = make_scene("flag", bench_cloth_params(side));  // bench-300's material
  PipelineOptions options{true, threads};
  options.adaptive_threads = false;
  options.force_general_path = path == Path::GeneralOnGrid;
  if (path != Path::IrregularMesh)
    return std::make_unique<Cloth>(scene, Precision::Float32, options);
  const auto model =
      build_mesh_model(irregular_sheet(static_cast<uint32_t>(side), scene.width), scene);
  return std::make_unique<Cloth>(scene, model, Precision::Float32, options);
}

void forces(benchmark::State& state, Path path) {
  const auto cloth =
      make_cloth(path, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const clothlab_system& system = cloth->system();
  void* a = system.alloc_vector(system.context);
  for (auto _ : state) {
    system.eval_acceleration(system.context, 0.0, system.x, system.v, a);
    benchmark::ClobberMemory();
  }
  state.counters["springs_per_s"] =
      benchmark::Counter(static_cast<double>(cloth->model()->spring_count()),
                         benchmark::Counter::kIsIterationInvariantRate);
}

void rk4_step(benchmark::State& state, Path path) {
  const auto cloth =
      make_cloth(path, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  static constexpr double c[4] = {0, 0.5, 0.5, 1}, alpha[4] = {0, 0.5, 0.5, 1};
  static constexpr double x_coupling[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0.25, 0, 0, 0, 0, 0.5, 0};
  static constexpr double v_coupling[16] = {0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1, 0};
  static constexpr double x_weights[4] = {1.0 / 6, 1.0 / 6, 1.0 / 6, 0};
  static constexpr double v_weights[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
  const clothlab_rkn_scheme scheme{sizeof scheme, 4,          c,         alpha,
                                   x_coupling,    v_coupling, x_weights, v_weights};
  const clothlab_system& system = cloth->system();
  system.reserve_rkn(system.context, 4);
  const Cloth::RawState start = [&] {
    Cloth::RawState raw;
    cloth->copy_raw_state(raw);
    return raw;
  }();
  int steps = 0;
  for (auto _ : state) {
    system.step_rkn(system.context, 0.0, 1e-4, &scheme);
    if (++steps % 1000 == 0) {  // back to rest before the flag goes anywhere odd
      state.PauseTiming();
      cloth->set_raw_state(start);
      state.ResumeTiming();
    }
  }
  state.counters["springs_per_s"] =
      benchmark::Counter(4.0 * static_cast<double>(cloth->model()->spring_count()),
                         benchmark::Counter::kIsIterationInvariantRate);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int threads : {1, 2}) b->Args({300, threads});
  b->ArgNames({"side", "threads"})->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(forces, grid, Path::Grid)->Apply(sizes);
BENCHMARK_CAPTURE(forces, general_on_grid, Path::GeneralOnGrid)->Apply(sizes);
BENCHMARK_CAPTURE(forces, irregular_mesh, Path::IrregularMesh)->Apply(sizes);
BENCHMARK_CAPTURE(rk4_step, grid, Path::Grid)->Apply(sizes);
BENCHMARK_CAPTURE(rk4_step, general_on_grid, Path::GeneralOnGrid)->Apply(sizes);
BENCHMARK_CAPTURE(rk4_step, irregular_mesh, Path::IrregularMesh)->Apply(sizes);

}  // namespace
}  // namespace clothlab::bench

BENCHMARK_MAIN();
